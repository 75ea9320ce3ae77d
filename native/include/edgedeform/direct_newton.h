// Projected Newton with a direct factorization (docs/design.md §4, "Reaching the fixed point"):
// each step solves K delta = A (G(y) - y) = b exactly, K the Newton matrix assembled term by
// term and factored (newton_factor.h).
// - lambda = 1 on every term: K is the energy's Hessian (halved) at the fitted rotations and
//   the iteration is descent on E: far from the solution, where K is indefinite, the per-node
//   positive model (linearize_fit) replaces it; the true K once it factors positive definite.
//   No shift along A: the soft modes are the ones a step must resolve. Armijo on E.
// - lambda < 1: K is not symmetric; its LU; a line search on |A F| (each trial one global step).
// A step that fails its line search, or a K that does not factor, gives way to a few plain
// steps. Converged when a step of the true K (full, exact) is below the tolerance: that step
// is the distance of the point it started from, and the point after it is closer.
#pragma once

#include <limits>

#include "edgedeform/fixed_point_problem.h"

namespace edgedeform {

struct SolveResult;

// lambda = 1: how much of K is projected (linearize_fit's `projection`): 0 is K itself, 1
// the per-node positive model. A K that does not factor moves up a level, a full step down.
constexpr double kProjectionLevels[] = {0.0, 0.5, 0.8, 0.9, 0.95, 0.99, 1.0};
constexpr int kProjectionLevelCount = sizeof(kProjectionLevels) / sizeof(kProjectionLevels[0]);

struct DirectNewtonSettings {
  int max_iterations = 2000;  // global steps (evaluations of G), as for the other methods
  double tolerance = 1e-3;    // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;          // rest bounding-box diagonal
  bool descent = false;       // lambda = 1 on every term: E is the merit, K symmetric
  // lambda = 1: the projection level a fresh start begins at (an index of kProjectionLevels).
  int start_level = 3;
  // lambda = 1: a trial that fails Armijo is corrected before it is cut: 0 no, 1 by a plain
  // step, 2 by a chord step (the same factor).
  int correction = 0;
  // lambda = 1: a full step of a projected model goes on, doubling, up to this multiple of
  // itself while E falls (0: not).
  double extrapolate = 0.0;
  // lambda = 1: full steps at a level before the next lower one is tried.
  int level_patience = 1;
  bool ladder = true;  // EXPERIMENT: partial projections; false: K or the per-node model only
};

// The strategy's state between calls (a warm solve with still targets continues it).
struct DirectNewtonMemory {
  int plain_steps_left = 1;   // plain steps before the next Newton step
  int level = 0;              // lambda = 1: index of the projection in kProjectionLevels
  int held = 0;               // full steps since the level last changed
  bool candidate = false;     // lambda = 1: the last step was K's own, full and small
  void reset(int plain_steps, int start_level) {
    *this = DirectNewtonMemory();
    plain_steps_left = plain_steps;
    level = start_level;
  }
};

// The iterate the strategy continues: y (#free x 3), the fit at y (when fitted), E(y).
struct DirectNewtonPoint {
  Eigen::MatrixXd& y;
  LocalFit& fit;
  double& energy;
  bool& fitted;  // fit = fit(y); false for a cold start's first step (R = I, s = 1)
  DirectNewtonMemory& memory;
};

// Runs until converged or max_iterations global steps; fills result's iterations,
// energies, residuals, distance_estimate, converged, newton counters and warnings (throws
// SolveInterrupted when asked to stop). Never ends worse (in its merit) than its best point.
void direct_newton_solve(FixedPointProblem& problem, const DirectNewtonSettings& settings, DirectNewtonPoint point,
                         SolveResult& result);

}  // namespace edgedeform
