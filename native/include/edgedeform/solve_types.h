// What a solve is asked and what it returns: the options of Deformer::solve and the strategies'
// settings they come from, and SolveResult, which every strategy fills. At the bottom of the
// solver's layers: the strategies (fixed_point_iteration.h, projected_newton.h) and the
// Deformer include it, it includes only the core's types.
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "edgedeform/types.h"

namespace edgedeform {

enum class Acceleration { None, Anderson, Newton };
const char* acceleration_name(Acceleration a);
// "none" | "anderson" | "newton"; anything else throws std::invalid_argument.
Acceleration parse_acceleration(const std::string& name);

// The Newton method's settings (acceleration Newton).
struct NewtonOptions {
  // A cold or moved-target start first runs up to this many Anderson iterations: they settle
  // the stiff part of the error cheaply and keep the solve in the basin Anderson finds (the
  // head lift without them: another minimum, 3.6e-3 of the diagonal away; docs/decisions/0029).
  int lead_in = 100;
  // For the diagnostic that chose the method (bench/bench_newton.py, docs/decisions/0029):
  // lambda = 1: "ladder" (default) projects only the terms below a level that factors;
  // "full" uses K itself where it factors and else projects every indefinite term.
  // `lifted` (default) moves each trial along the step's rotation response, else straight.
  bool ladder = true;
  bool lifted = true;
};

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
  Acceleration acceleration = Acceleration::Anderson;
  int anderson_window = 5;
  // Plain/Anderson: before a convergence claim, estimate J_G's largest modulus by Arnoldi
  // steps at the point (claim_check.h) and claim only if the bound with it holds too.
  bool verify_claims = false;
  NewtonOptions newton;
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
  int accelerated_steps = 0, rejected_steps = 0;  // Anderson steps taken; discarded by the safeguard
  int newton_steps = 0;                         // Newton: steps taken
  int line_search_failures = 0;                 // Newton steps that gave way to plain steps
  int newton_factorizations = 0;                // Newton: factorizations of K (failed ones included)
  int newton_fallbacks = 0;                     // Newton's steps stopped lowering the merit: Anderson finished
  double assemble_ms = 0.0, newton_factor_ms = 0.0;  // Newton: assembling K, factoring it (totals)
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
