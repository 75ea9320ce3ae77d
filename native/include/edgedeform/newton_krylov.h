// Inexact Newton on F(y) = y - G(y) (docs/design.md §4, "Reaching the fixed point"): the step
// solves (I - J_G) delta = -F, as K delta = A (G(y) - y) with K = A - D
// (fixed_point_linearization.h), by FGMRES preconditioned with the coarse space
// (coarse_space.h) and the existing factor of A; forcing terms after Eisenstat and Walker;
// an Armijo line search on E where lambda = 1 on every term (the iteration is then descent
// on E), on |A F| otherwise. A step that fails its line search gives way to a few plain
// local/global steps; the solve returns the best point it held.
#pragma once

#include <functional>
#include <limits>
#include <memory>

#include "edgedeform/coarse_space.h"
#include "edgedeform/fixed_point_linearization.h"
#include "edgedeform/fixed_point_problem.h"

namespace edgedeform {

struct SolveResult;

struct NewtonSettings {
  int max_iterations = 2000;   // global steps (evaluations of G), as for the other methods
  double tolerance = 1e-3;     // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;           // rest bounding-box diagonal
  bool descent = false;        // lambda = 1 on every term: E is the merit
  int krylov_iterations = 30;  // most products with K per Newton step
  const CoarseBasis* coarse = nullptr;     // none: the one-level preconditioner A^-1
  const SparseMatrix* coarse_stiffness = nullptr;  // U^T A U of that basis
  CoarseCorrection* coarse_correction = nullptr;   // kept by the caller: its analysis is reused
};

// The strategy's state between calls: a warm solve with unchanged targets continues where
// the last call stopped (live editing standing still), instead of starting over.
struct NewtonMemory {
  int plain_steps_left = 2;   // plain steps before the next Newton step
  double previous_b_norm = -1.0, previous_eta = 0.1;  // for the forcing term
  double last_exact_step = std::numeric_limits<double>::infinity();  // of the last full Newton step, / diag
  double shift = 0.0;         // Levenberg-Marquardt shift (relative to A)
  bool near_minimum = false;  // lambda = 1: the true Hessian instead of the positive model
  int coarse_age = 1 << 20;   // Newton steps since the coarse operator was assembled
  double coarse_shift = -1.0; // the shift it was factored with
  SparseMatrix coarse_unshifted;  // U^T K U as last assembled (without the shift)
  // Starts afresh: `plain_steps` plain steps first; at lambda < 1 there is no positive model.
  void reset(int plain_steps, bool descent) {
    *this = NewtonMemory();
    plain_steps_left = plain_steps;
    near_minimum = !descent;
  }
};

// The iterate the strategy continues: y, the fit at y (when fitted), E(y).
struct IterationPoint {
  Eigen::MatrixXd& y;
  LocalFit& fit;
  double& energy;
  bool& fitted;  // fit = fit(y); false for a cold start's first step (R = I, s = 1)
  NewtonMemory& memory;
};

// Runs until converged or max_iterations global steps; fills result's iterations,
// energies, residuals, distance_estimate, converged, newton counters and warnings (throws
// SolveInterrupted when asked to stop).
void newton_krylov_solve(FixedPointProblem& problem, const NewtonSettings& settings, IterationPoint point,
                         SolveResult& result);

}  // namespace edgedeform
