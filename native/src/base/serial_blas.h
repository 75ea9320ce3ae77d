// Runs the BLAS calls that CHOLMOD's supernodal factorization makes on one thread, for the
// lifetime of the guard, where the BLAS is OpenBLAS (Debian's, or the copy auditwheel puts
// in the wheel).
//
// Why: a multi-threaded BLAS splits CHOLMOD's dense updates by its thread count, which
// changes their summation order: the factor, and so every solve, then differs in its last
// bits between OMP_NUM_THREADS=1 and 2, and a soft problem (lambda < 1) can settle at
// another resting place (measured on the dino lift, edge, lambda 0.5: 30 plain iterations
// 4.8e-14 apart, and iterations amplify such differences; with the BLAS on one thread, equal).
//
// How: OpenBLAS's own openblas_set_num_threads, looked up at run time among the loaded
// libraries (dlsym; GetProcAddress over the process's modules on Windows, where a weak
// reference never resolves against a DLL), so that a build against another BLAS, or none,
// links and runs unchanged (without reproducibility across thread counts).
#pragma once

namespace edgedeform {

class SerialBlas {
 public:
  SerialBlas();
  ~SerialBlas();
  SerialBlas(const SerialBlas&) = delete;
  SerialBlas& operator=(const SerialBlas&) = delete;
  // Whether the process's BLAS can be limited (OpenBLAS found).
  static bool available();
  // The BLAS's current thread count (OpenBLAS's openblas_get_num_threads); 0 without OpenBLAS.
  static int blas_threads();
};

}  // namespace edgedeform
