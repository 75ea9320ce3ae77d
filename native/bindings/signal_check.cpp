#include "signal_check.h"

#include <stdexcept>

namespace edgedeform::bindings {

SignalCheck::SignalCheck(std::chrono::milliseconds interval)
    : interval_(interval), last_check_(std::chrono::steady_clock::now()) {}

std::function<bool()> SignalCheck::callback() {
  return [this] { return poll(); };
}

bool SignalCheck::poll() {
  // Once seen, a stop request holds until raised: a caller that only breaks its own loop
  // must not use it up before the one that throws asks (measured when an inner solver loop
  // polled it: Ctrl-C was lost there, and the solve ran on for a minute).
  if (pending_) return true;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_check_ < interval_) return false;
  last_check_ = now;
  py::gil_scoped_acquire gil;
  // Runs the Python-level handlers of signals that arrived (main thread only; elsewhere 0).
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
