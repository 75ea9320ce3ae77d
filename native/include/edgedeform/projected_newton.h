// Projected Newton with a direct factorization (docs/design.md §4, "Reaching the fixed point";
// docs/decisions/0029): each step solves K delta = A (G(y) - y) = b exactly, K the Newton
// matrix assembled term by term and factored (newton_factor.h).
//
// Only where lambda = 1 on every term: K is then the energy's Hessian (halved) at the fitted
// rotations, and the solve is descent on E. Below lambda 1 (K not symmetric, no energy the
// scheme descends) an LU step with a line search on |A F| lost to Anderson on every mesh
// measured and failed on the koala (record 0029): the Deformer runs Anderson there.
// - Direction: K is positive definite only very near a minimum, so a step factors K with as
//   little projected as factors: the terms whose generalized eigenvalue lies below a level
//   (kProjectionLevels) made flat (linearize_fit), the level raised while K does not factor,
//   lowered after a full step. No shift along A: it would damp the soft modes a step must
//   resolve.
// - Line search: the step is lifted into the fit (each term's rotation turned by its linear
//   response, then a global step: a turning part moves on its arc, where a straight step
//   stretches it), Armijo on E, cuts by quadratic interpolation.
//
// Converged: a full step of K itself (no projection) below the tolerance, twice in a row,
// since a point where K factors can lie beside a saddle where it does not. A solve whose line
// searches keep failing gives up (the caller goes on with Anderson).
#pragma once


#include "edgedeform/fixed_point_problem.h"
#include "edgedeform/iteration_point.h"
#include "edgedeform/solve_types.h"

namespace edgedeform {

// How much of K a step projects (linearize_fit's `projection`): 0 is K itself, 1
// every indefinite term.
constexpr double kProjectionLevels[] = {0.0, 0.5, 0.8, 0.9, 0.95, 0.99, 1.0};
constexpr int kProjectionLevelCount = sizeof(kProjectionLevels) / sizeof(kProjectionLevels[0]);
// The level a fresh start tries first (0.9): measured on the koala, dino, head and Spot lifts
// (docs/decisions/0029), K itself almost never factors away from the solution.
constexpr int kStartLevel = 3;

struct NewtonSettings {
  int max_iterations = 2000;  // global steps (evaluations of G), as for the other methods
  double tolerance = 1e-3;    // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;          // rest bounding-box diagonal
  // For the diagnostic that chose these (bench/bench_newton.py, record 0029):
  // the level ladder, or K itself where it factors and else every indefinite term projected;
  // trials lifted into the fit, or straight (y + alpha delta).
  bool ladder = true;
  bool lifted = true;
};

// The strategy's state between calls: a warm solve with still targets continues it.
struct NewtonMemory {
  int plain_steps_left = 1;   // plain steps before the next Newton step
  int level = kStartLevel;    // index into kProjectionLevels
  bool candidate = false;     // the last step was K's own, full and small
  int failures = 0;           // line searches failed in a row
  // Starts afresh: `plain_steps` plain steps first.
  void reset(int plain_steps) {
    *this = NewtonMemory();
    plain_steps_left = plain_steps;
  }
};

enum class NewtonEnd {
  Converged,
  Stopped,  // max_iterations, or non-finite positions (a warning says which)
  GaveUp,   // its steps stopped lowering the merit; y and its fit are consistent
};

// Runs until one of NewtonEnd; fills result's iterations, energies, residuals,
// distance_estimate, converged, Newton counters and warnings (throws SolveInterrupted when
// asked to stop; the caller then marks the point unfitted). Never ends worse (in its merit)
// than its best point.
NewtonEnd projected_newton_solve(FixedPointProblem& problem, const NewtonSettings& settings, IterationPoint& point,
                                 LocalFit& fit, NewtonMemory& memory, SolveResult& result);

}  // namespace edgedeform
