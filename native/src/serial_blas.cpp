#include "edgedeform/serial_blas.h"

#include <mutex>

extern "C" {
// OpenBLAS's thread controls; null where the BLAS is not OpenBLAS.
void openblas_set_num_threads(int threads) __attribute__((weak));
int openblas_get_num_threads() __attribute__((weak));
}

namespace edgedeform {

namespace {
// The setting is process-wide: nested or concurrent guards share one count.
std::mutex guard_mutex;
int live_guards = 0;
int saved_threads = -1;
}  // namespace

bool SerialBlas::available() { return openblas_set_num_threads != nullptr && openblas_get_num_threads != nullptr; }

SerialBlas::SerialBlas() {
  if (!available()) return;
  const std::lock_guard<std::mutex> lock(guard_mutex);
  if (live_guards++ == 0) {
    saved_threads = openblas_get_num_threads();
    if (saved_threads != 1) openblas_set_num_threads(1);
  }
}

SerialBlas::~SerialBlas() {
  if (!available()) return;
  const std::lock_guard<std::mutex> lock(guard_mutex);
  if (--live_guards == 0 && saved_threads > 1) openblas_set_num_threads(saved_threads);
}

}  // namespace edgedeform
