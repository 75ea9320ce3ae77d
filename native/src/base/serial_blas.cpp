#include "base/serial_blas.h"

#include <mutex>

#if defined(_WIN32)
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>
#include <tlhelp32.h>
#else
#include <dlfcn.h>
#endif

namespace edgedeform {

namespace {
using SetThreads = void (*)(int);
using GetThreads = int (*)();

struct OpenBlasControls {
  SetThreads set = nullptr;
  GetThreads get = nullptr;
  bool found() const { return set != nullptr && get != nullptr; }
};

// OpenBLAS's thread controls, looked up at run time in the libraries the process has loaded
// (a weak reference resolves only against an ELF shared library, never against a Windows DLL,
// and does not link at all on macOS against a BLAS that lacks the symbol). Looked up on every
// guard: a lookup costs microseconds against a factorization's milliseconds, and a BLAS loaded
// after the first solve is still found.
#if defined(_WIN32)
OpenBlasControls lookup(HMODULE module) {
  return {reinterpret_cast<SetThreads>(reinterpret_cast<void*>(GetProcAddress(module, "openblas_set_num_threads"))),
          reinterpret_cast<GetThreads>(reinterpret_cast<void*>(GetProcAddress(module, "openblas_get_num_threads")))};
}

OpenBlasControls find_openblas() {
#ifdef EDGEDEFORM_BLAS_DLL_NAME
  // First the DLL this build's CHOLMOD calls (edgedeform_openblas.dll): SciPy's OpenBLAS,
  // loaded before it, exports the same controls, and limiting that one would leave CHOLMOD's
  // BLAS threaded.
  if (HMODULE own = GetModuleHandleA(EDGEDEFORM_BLAS_DLL_NAME)) {
    const OpenBlasControls controls = lookup(own);
    if (controls.found()) return controls;
  }
#endif
  // Then every module of the process: a BLAS DLL has no fixed name (libopenblas.dll,
  // openblas.dll, a copy renamed by delvewheel).
  OpenBlasControls controls;
  HANDLE snapshot = CreateToolhelp32Snapshot(TH32CS_SNAPMODULE, GetCurrentProcessId());
  if (snapshot == INVALID_HANDLE_VALUE) return controls;
  MODULEENTRY32W entry;
  entry.dwSize = sizeof(entry);
  for (BOOL more = Module32FirstW(snapshot, &entry); more; more = Module32NextW(snapshot, &entry)) {
    controls = lookup(entry.hModule);
    if (controls.found()) break;
  }
  CloseHandle(snapshot);
  return controls;
}
#else
OpenBlasControls lookup(void* handle) {
  return {reinterpret_cast<SetThreads>(dlsym(handle, "openblas_set_num_threads")),
          reinterpret_cast<GetThreads>(dlsym(handle, "openblas_get_num_threads"))};
}

OpenBlasControls find_openblas() {
  // First this library's own dependencies (where CHOLMOD's BLAS is: inside Python the module
  // is loaded RTLD_LOCAL, so the global scope does not see them), then the global scope.
  OpenBlasControls controls;
  Dl_info self;
  if (dladdr(reinterpret_cast<void*>(&find_openblas), &self) != 0 && self.dli_fname != nullptr) {
    if (void* handle = dlopen(self.dli_fname, RTLD_LAZY | RTLD_NOLOAD)) {
      controls = lookup(handle);
      dlclose(handle);  // only drops the reference RTLD_NOLOAD added
    }
  }
  if (!controls.found()) controls = lookup(RTLD_DEFAULT);
  return controls;
}
#endif

// The setting is process-wide: nested or concurrent guards share one count.
std::mutex guard_mutex;
int live_guards = 0;
int saved_threads = -1;
OpenBlasControls guarded;  // the controls the outermost live guard changed
}  // namespace

bool SerialBlas::available() { return find_openblas().found(); }

int SerialBlas::blas_threads() {
  const OpenBlasControls controls = find_openblas();
  return controls.found() ? controls.get() : 0;
}

SerialBlas::SerialBlas() {
  const std::lock_guard<std::mutex> lock(guard_mutex);
  if (live_guards++ != 0) return;
  guarded = find_openblas();
  if (!guarded.found()) return;
  saved_threads = guarded.get();
  if (saved_threads != 1) guarded.set(1);
}

SerialBlas::~SerialBlas() {
  const std::lock_guard<std::mutex> lock(guard_mutex);
  if (--live_guards != 0) return;
  if (guarded.found() && saved_threads > 1) guarded.set(saved_threads);
  guarded = {};
}

}  // namespace edgedeform
