// Project exceptions. Bad arguments use the standard ones so that the bindings map them:
// std::invalid_argument -> ValueError, std::out_of_range -> IndexError.
#pragma once

#include <stdexcept>

namespace edgedeform {

// The global matrix could not be factored (not positive definite).
struct FactorizationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// set_constraints with a roi_radius that leaves no vertex free (a ValueError in Python:
// edgedeform.NoFreeVertexError, which callers catch by type, not by its words).
struct NoFreeVertexError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// SolveOptions::interrupt_requested returned true: the solve stopped between iterations.
// The Deformer stays usable; the next solve does not warm-start from the interrupted one.
struct SolveInterrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace edgedeform
