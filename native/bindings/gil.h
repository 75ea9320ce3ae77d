// The bindings' long core calls run without the GIL (a solve in one thread leaves Python
// free in the others). Coming back is the delicate part: a thread that takes the GIL while
// the interpreter shuts down (a daemon thread, or one whose join Ctrl-C interrupted, at
// exit) is ended by CPython 3.11-3.13 with pthread_exit, and that unwinding through C++
// frames (pybind11's gil_scoped_release destructor is noexcept) aborts the whole process:
// "terminate called without an active exception". Such a thread waits here for the
// process to end instead, as CPython 3.14 makes its own threads do.
#pragma once

#include <exception>
#include <optional>
#include <type_traits>
#include <utility>

#include <pybind11/pybind11.h>

namespace edgedeform::bindings {

// Whether the interpreter is shutting down; callable without the GIL.
bool interpreter_finalizing();

// Takes the GIL back after PyEval_SaveThread, or never returns when the interpreter is
// shutting down. Not a destructor, so that the pthread_exit CPython may still call (the
// shutdown began while this thread waited for the GIL) can unwind through it.
void return_to_python(PyThreadState* state);

// work() without the GIL; its result, or its exception rethrown once the GIL is back.
template <class Work>
auto without_gil(Work&& work) -> decltype(work()) {
  using Result = decltype(work());
  std::exception_ptr error;
  PyThreadState* state = PyEval_SaveThread();
  if constexpr (std::is_void_v<Result>) {
    try {
      work();
    } catch (...) {
      error = std::current_exception();
    }
    return_to_python(state);
    if (error) std::rethrow_exception(error);
  } else {
    std::optional<Result> result;
    try {
      result.emplace(work());
    } catch (...) {
      error = std::current_exception();
    }
    return_to_python(state);
    if (error) std::rethrow_exception(error);
    return std::move(*result);
  }
}

}  // namespace edgedeform::bindings
