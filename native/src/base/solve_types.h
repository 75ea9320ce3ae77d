// What a solve is asked and what it returns: the options of Deformer::solve and the strategies'
// settings they come from, and SolveResult, which every strategy fills. At the bottom of the
// solver's layers: the strategies (fixed_point_iteration.h, quasi_newton.h) and the
// Deformer include it, it includes only the core's types.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "base/types.h"

namespace edgedeform {

// Automatic: L-BFGS where lambda = 1 on every term, else Anderson (the measured rule of
// docs/decisions/0070).
enum class Acceleration { Automatic, Lbfgs, Anderson, None };
const char* acceleration_name(Acceleration a);
// "auto" | "lbfgs" | "anderson" | "none"; anything else throws std::invalid_argument.
Acceleration parse_acceleration(const std::string& name);

// The range of an integer option of a solve: Deformer::solve refuses a value outside it
// (check_in_range), and the bindings give the same message for a Python int too large for
// an int.
struct IntRange {
  const char* name;
  int low, high;
};
inline constexpr IntRange kMaxIterationsRange{"max_iterations", 1, std::numeric_limits<int>::max()};
inline constexpr IntRange kAndersonWindowRange{"anderson_window", 1, 50};
// "max_iterations must be an integer in [1, 2147483647], got 0" (`value` as written).
std::string out_of_range_message(const IntRange& range, const std::string& value);
// Throws std::invalid_argument with that message when `value` is outside the range.
void check_in_range(const IntRange& range, int value);

struct SolveOptions {
  int max_iterations = 2000;
  // Converged: the estimated largest vertex distance to the fixed point is below
  // tolerance * (rest bounding-box diagonal). See convergence.h.
  double tolerance = 1e-3;
  bool warm_start = true;
  std::optional<RowMatrixX3d> initial;  // start with a local step on these positions
  Acceleration acceleration = Acceleration::Automatic;
  int anderson_window = 5;
  // Before a convergence claim, estimate J_G's largest modulus by Arnoldi
  // steps at the point (claim_check.h) and claim only if the bound with it holds too.
  bool verify_claims = false;
  // Asked once per iteration (called from the solving thread); returning true stops the
  // solve with SolveInterrupted. The Python bindings check for Ctrl-C here, so the core
  // needs no Python.
  std::function<bool()> interrupt_requested;
};

struct SolveResult {
  RowMatrixX3d positions;
  int iterations = 0;
  std::vector<double> energies;                 // after each iteration
  // Per iteration: |G(y) - y|_inf / diag for the point y its global step started from
  // (for the plain method |x_k - x_{k-1}|, the largest vertex move, over the rest diagonal).
  std::vector<double> residuals;
  double distance_estimate = 0.0;               // of the result to the fixed point, / diag
  // Anderson: accelerated steps taken and discarded by the safeguard; L-BFGS: quasi-Newton
  // steps taken and directions that failed their line search (the plain step instead).
  int accelerated_steps = 0, rejected_steps = 0;
  int line_search_fits = 0;                     // L-BFGS: local fits beyond one per iteration
  std::string method;                           // the strategy that ran: "lbfgs", "anderson" or "none"
  int claim_checks = 0, refused_claims = 0;     // verify_claims: checks made, claims refused
  std::optional<double> initial_energy;         // energy of `initial`, when given
  bool converged = false;
  std::vector<std::string> warnings;
  double factor_ms = 0.0;                       // assembly + factorization in this call
  double local_ms = 0.0, rhs_ms = 0.0, solve_ms = 0.0;  // totals over the iterations
  int free_vertices = 0;
  int active_nodes = 0;
};

// The warning of a solve that stopped at max_iterations, one text for every strategy:
// `estimate_is` names what distance_estimate (a fraction of the diagonal) is, e.g. "the
// estimated distance to the fixed point is"; when it is infinite, `unknown_because` says why.
std::string not_converged_warning(int max_iterations, double distance_estimate, double tolerance,
                                  const std::string& estimate_is, const std::string& unknown_because = "");

}  // namespace edgedeform
