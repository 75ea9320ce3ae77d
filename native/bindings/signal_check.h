// Ctrl-C during a long solve. The core asks SolveOptions::interrupt_requested once per
// iteration; this supplies it from Python's signal handling without keeping the GIL. Only
// the main thread runs signal handlers, so a solve in another thread never takes the GIL
// here: it only stops when the interpreter shuts down (gil.h says why that matters).
#pragma once

#include <chrono>
#include <functional>
#include <optional>

#include <pybind11/pybind11.h>

namespace edgedeform::bindings {

namespace py = pybind11;

class SignalCheck {
 public:
  // At most one GIL round trip per `interval`: Ctrl-C is seen within one iteration plus
  // this, and a fast iteration loop pays nothing measurable.
  // Made with the GIL held, in the thread that solves.
  explicit SignalCheck(std::chrono::milliseconds interval = std::chrono::milliseconds(50));
  // For SolveOptions::interrupt_requested; called without the GIL, from the solving thread.
  // True from the first time a signal's handler raised until raise_pending, and once the
  // interpreter shuts down.
  std::function<bool()> callback();
  // After the core stopped (SolveInterrupted), with the GIL held: raises the Python error
  // the signal handler set (KeyboardInterrupt for Ctrl-C).
  [[noreturn]] void raise_pending();

 private:
  bool poll();

  bool main_thread_;
  std::chrono::milliseconds interval_;
  std::chrono::steady_clock::time_point last_check_;
  std::optional<py::error_already_set> pending_;
};

}  // namespace edgedeform::bindings
