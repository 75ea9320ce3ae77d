// The plain local/global iteration x -> G(x) = global(local(x)) of docs/design.md §4, with
// Anderson acceleration unless disabled, on the same FixedPointProblem as L-BFGS
// (quasi_newton.h), so that the strategies are interchangeable.
#pragma once

#include <Eigen/Core>

#include "strategies/anderson.h"
#include "strategies/convergence.h"
#include "strategies/fixed_point_problem.h"
#include "base/iteration_point.h"
#include "base/solve_types.h"

namespace edgedeform {

struct PlainAndersonSettings {
  int max_iterations = 2000;  // global steps
  double tolerance = 1e-3;    // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;          // rest bounding-box diagonal
  bool descent = false;       // lambda = 1 on every term: E decides the Anderson safeguard
  bool accelerate = true;     // Anderson; false: plain steps only
  bool verify_claims = false; // a claim is checked by Arnoldi on J_G first (claim_check.h)
};

// The strategy's state between calls: a warm solve with unchanged targets continues the
// last call's Anderson history and rate estimate.
struct PlainAndersonMemory {
  Eigen::MatrixXd g, next;    // G(y); the next point
  Eigen::MatrixXd base_step;  // plain step of the last accepted point (lambda < 1 fallback)
  Eigen::MatrixXd rhs;        // global-step scratch, reused by every iteration
  double best_residual = 0.0;  // smallest residual of a G pair since the targets were set
  bool y_accelerated = false;  // y came from an Anderson step not yet judged
  AndersonAccelerator anderson;
  ConvergenceMonitor monitor;

  // Starts afresh for `free_vertices` free vertices (new targets or a cold start).
  void restart(int free_vertices, int window);
  // A continued solve asks for another Anderson window: the history restarts at that size.
  void set_window(int free_vertices, int window) {
    if (anderson.window() != window) anderson.resize(3 * static_cast<Eigen::Index>(free_vertices), window);
  }
  // Another strategy moved the iterate: the history and rate estimate no longer describe it.
  void forget() {
    anderson.reset();
    monitor.reset();
    y_accelerated = false;
  }
};

// Runs until converged or max_iterations global steps; fills result's iterations,
// energies, residuals, distance_estimate, converged, accelerated and rejected steps, and
// warnings (throws SolveInterrupted when the problem asks to stop; the caller then marks the
// point unfitted). On return point.y holds the result and fit its local fit.
void plain_anderson_solve(FixedPointProblem& problem, const PlainAndersonSettings& settings, IterationPoint& point,
                          LocalFit& fit, PlainAndersonMemory& memory, SolveResult& result);

}  // namespace edgedeform
