// Inexact Newton on F(y) = y - G(y) (DESIGN §2, "Reaching the fixed point"): the step
// solves (I - J_G) delta = -F, as K delta = A (G(y) - y) with K = A - D
// (fixed_point_linearization.h), by FGMRES preconditioned with the coarse space
// (coarse_space.h) and the existing factor of A; forcing terms after Eisenstat and Walker;
// an Armijo line search on E where lambda = 1 on every term (the iteration is then descent
// on E), on |A F| otherwise. A step that fails its line search gives way to a few plain
// local/global steps; the solve returns the best point it held.
#pragma once

#include <functional>
#include <memory>

#include "edgedeform/coarse_space.h"
#include "edgedeform/fixed_point_linearization.h"

namespace edgedeform {

struct SolveResult;

// What the strategy needs of the problem: the local fit, the global step, A and its factor.
class FixedPointProblem {
 public:
  virtual ~FixedPointProblem() = default;
  // fit := the local fit at free positions y (#free x 3); returns E(y). The node positions
  // of the last call are those linearize() uses.
  virtual double local_fit(const Eigen::MatrixXd& y, LocalFit& fit) = 0;
  // rhs := the global step's right side for `fit`, g := A^-1 rhs (= G(y) for fit = fit(y)).
  virtual void global_step(const LocalFit& fit, Eigen::MatrixXd& rhs, Eigen::MatrixXd& g) = 0;
  virtual void solve_A(const Eigen::MatrixXd& r, Eigen::MatrixXd& z) = 0;
  virtual const SparseMatrix& A() const = 0;
  // The linearization at the point of the last local_fit call, whose fit `fit` is.
  virtual std::unique_ptr<FixedPointLinearization> linearize(const LocalFit& fit) = 0;
  // Asked between steps and inside the Krylov solve: true stops the solve.
  virtual bool interrupt_requested() = 0;
};

struct NewtonSettings {
  int max_iterations = 2000;   // global steps (evaluations of G), as for the other methods
  double tolerance = 1e-3;     // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;           // rest bounding-box diagonal
  bool descent = false;        // lambda = 1 on every term: E is the merit
  int krylov_iterations = 30;  // most products with K per Newton step
  int plain_steps_first = 2;   // plain steps before the first Newton step of a solve
  const CoarseBasis* coarse = nullptr;     // none: the one-level preconditioner A^-1
  const SparseMatrix* coarse_stiffness = nullptr;  // U^T A U of that basis
  CoarseCorrection* coarse_correction = nullptr;   // kept by the caller: its analysis is reused
};

// The iterate the strategy continues: y, the fit at y (when fitted), E(y).
struct IterationPoint {
  Eigen::MatrixXd& y;
  LocalFit& fit;
  double& energy;
  bool& fitted;  // fit = fit(y); false for a cold start's first step (R = I, s = 1)
};

// Runs until converged or max_iterations global steps; fills result's iterations,
// energies, residuals, distance_estimate, converged, newton counters and warnings (throws
// SolveInterrupted when asked to stop).
void newton_krylov_solve(FixedPointProblem& problem, const NewtonSettings& settings, IterationPoint point,
                         SolveResult& result);

}  // namespace edgedeform
