// A stand-in for OpenBLAS's thread controls, built as a shared library (a DLL on Windows) that
// test_serial_blas.cpp loads at run time: it proves SerialBlas finds a BLAS it was not linked
// against, as it must find OpenBLAS's DLL on Windows. Starts at 4 threads, so that a guard's
// restore is visible.
#if defined(_WIN32)
#define FAKE_OPENBLAS_EXPORT __declspec(dllexport)
#else
#define FAKE_OPENBLAS_EXPORT __attribute__((visibility("default")))
#endif

namespace {
int threads = 4;
}

extern "C" {
FAKE_OPENBLAS_EXPORT void openblas_set_num_threads(int n) { threads = n; }
FAKE_OPENBLAS_EXPORT int openblas_get_num_threads() { return threads; }
}
