// SerialBlas finds OpenBLAS's thread controls at run time, in a library it was not linked
// against (a DLL on Windows, where the former weak references stayed null and the BLAS stayed
// threaded), and a guard runs the BLAS on one thread and restores its count afterwards.
#include <gtest/gtest.h>

#include <string>

#include "linear_algebra/build_info.h"
#include "base/serial_blas.h"

#if defined(_WIN32)
#include <windows.h>
#else
#include <dlfcn.h>
#endif

namespace {

// Loads tests/cpp/fake_openblas.cpp's library into the process, visible to every lookup.
bool load_fake_openblas() {
#if defined(_WIN32)
  return LoadLibraryA(EDGEDEFORM_FAKE_OPENBLAS) != nullptr;  // next to the test program
#else
  return dlopen(EDGEDEFORM_FAKE_OPENBLAS, RTLD_NOW | RTLD_GLOBAL) != nullptr;
#endif
}

}  // namespace

TEST(SerialBlas, FindsOpenBlasAtRunTimeAndRunsItOnOneThread) {
  const bool linked = edgedeform::SerialBlas::available();
  // Debian's CHOLMOD calls OpenBLAS (libopenblas-dev): found through the library's own
  // dependencies, as the weak references found it before.
  if (std::string(edgedeform::solver_backend()) == "cholmod-supernodal") {
    EXPECT_TRUE(linked) << "CHOLMOD build, but OpenBLAS's thread controls were not found";
  }
  if (!linked) {
    EXPECT_EQ(edgedeform::SerialBlas::blas_threads(), 0);
    { const edgedeform::SerialBlas no_blas; }  // a no-op without OpenBLAS
  }
  ASSERT_TRUE(load_fake_openblas()) << "could not load " << EDGEDEFORM_FAKE_OPENBLAS;
  ASSERT_TRUE(edgedeform::SerialBlas::available()) << "a loaded OpenBLAS was not found";

  // The real OpenBLAS where the build has one (found first), else the stand-in (4 threads).
  const int before = edgedeform::SerialBlas::blas_threads();
  ASSERT_GE(before, 1);
  if (!linked) EXPECT_EQ(before, 4);
  {
    const edgedeform::SerialBlas outer;
    EXPECT_EQ(edgedeform::SerialBlas::blas_threads(), 1);
    {
      const edgedeform::SerialBlas inner;  // nested guards share one setting
      EXPECT_EQ(edgedeform::SerialBlas::blas_threads(), 1);
    }
    EXPECT_EQ(edgedeform::SerialBlas::blas_threads(), 1) << "an inner guard restored too early";
  }
  EXPECT_EQ(edgedeform::SerialBlas::blas_threads(), before);
}
