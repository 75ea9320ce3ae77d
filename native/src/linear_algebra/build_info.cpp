#include "linear_algebra/build_info.h"

#include <Eigen/Core>

#include "base/parallel.h"
#include "linear_algebra/sparse_cholesky.h"

namespace edgedeform {

const char* version() { return EDGEDEFORM_VERSION; }
const char* solver_backend() { return SparseCholesky::backend(); }

bool has_openmp() {
#ifdef _OPENMP
  return true;
#else
  return false;
#endif
}

int max_threads() { return parallel_threads(); }

std::string eigen_version() {
  return std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
         std::to_string(EIGEN_MINOR_VERSION);
}

std::string compiler() {
#if defined(__clang__)
  return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
  return std::string("gcc ") + __VERSION__;
#else
  return "unknown";
#endif
}

}  // namespace edgedeform
