#include "edgedeform/mesh_checks.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace edgedeform {

void check_finite(const RowMatrixX3d& X, const char* what) {
  for (Eigen::Index r = 0; r < X.rows(); ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(X(r, c)))
        throw std::invalid_argument(std::string(what) + " has a non-finite value (" +
                                    std::to_string(X(r, c)) + ") at row " + std::to_string(r));
}

void check_mesh(const RowMatrixX3d& V, const RowMatrixX3i& F) {
  if (V.rows() == 0) throw std::invalid_argument("V has no vertices");
  if (F.rows() == 0) throw std::invalid_argument("F has no faces");
  check_finite(V, "V");
  const int n = static_cast<int>(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      if (v < 0 || v >= n)
        throw std::out_of_range("F[" + std::to_string(f) + "] has vertex index " + std::to_string(v) +
                                ", outside [0, " + std::to_string(n) + ")");
    }
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
      throw std::invalid_argument("F[" + std::to_string(f) + "] repeats a vertex (" +
                                  std::to_string(F(f, 0)) + ", " + std::to_string(F(f, 1)) + ", " +
                                  std::to_string(F(f, 2)) + ")");
  }
}

void check_index_set(const std::vector<int>& indices, int n, const char* what) {
  std::vector<bool> seen(static_cast<size_t>(n), false);
  for (size_t k = 0; k < indices.size(); ++k) {
    const int v = indices[k];
    if (v < 0 || v >= n)
      throw std::out_of_range(std::string(what) + "[" + std::to_string(k) + "] = " + std::to_string(v) +
                              " is outside [0, " + std::to_string(n) + ")");
    if (seen[static_cast<size_t>(v)])
      throw std::invalid_argument(std::string(what) + " lists vertex " + std::to_string(v) + " twice");
    seen[static_cast<size_t>(v)] = true;
  }
}

std::vector<bool> referenced_vertices(const RowMatrixX3i& F, int n) {
  std::vector<bool> used(static_cast<size_t>(n), false);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<size_t>(F(f, k))] = true;
  return used;
}

}  // namespace edgedeform
