#include "signal_check.h"

#include <stdexcept>

#include "gil.h"

namespace edgedeform::bindings {

SignalCheck::SignalCheck(std::chrono::milliseconds interval)
    : main_thread_(PyThread_get_thread_ident() ==
                   py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>()),
      interval_(interval),
      last_check_(std::chrono::steady_clock::now()) {}

std::function<bool()> SignalCheck::callback() {
  return [this] { return poll(); };
}

bool SignalCheck::poll() {
  // Once seen, a stop request holds until raised: a caller that only breaks its own loop
  // must not use it up before the one that throws asks (measured when an inner solver loop
  // polled it: Ctrl-C was lost there, and the solve ran on for a minute).
  if (pending_) return true;
  if (!main_thread_) return interpreter_finalizing();  // never the GIL: see gil.h
  const auto now = std::chrono::steady_clock::now();
  if (now - last_check_ < interval_) return false;
  last_check_ = now;
  py::gil_scoped_acquire gil;
  // Runs the Python-level handlers of signals that arrived.
  if (PyErr_CheckSignals() == 0) return false;
  pending_.emplace();  // fetches the error the handler raised
  return true;
}

void SignalCheck::raise_pending() {
  if (!pending_) throw std::runtime_error("solve interrupted");
  py::error_already_set error = *pending_;
  pending_.reset();
  throw error;
}

}  // namespace edgedeform::bindings
