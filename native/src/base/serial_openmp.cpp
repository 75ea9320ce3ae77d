#include "base/serial_openmp.h"

#include <mutex>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace edgedeform {

#ifdef _OPENMP
namespace {
std::mutex guard_mutex;
int live_guards = 0;
int saved_levels = 0;  // max-active-levels before the first live guard
}  // namespace

SerialOpenMP::SerialOpenMP() {
  std::lock_guard<std::mutex> lock(guard_mutex);
  if (live_guards++ == 0) {
    saved_levels = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
  }
}

SerialOpenMP::~SerialOpenMP() {
  std::lock_guard<std::mutex> lock(guard_mutex);
  if (--live_guards == 0) omp_set_max_active_levels(saved_levels);
}
#else
SerialOpenMP::SerialOpenMP() = default;
SerialOpenMP::~SerialOpenMP() = default;
#endif

}  // namespace edgedeform
