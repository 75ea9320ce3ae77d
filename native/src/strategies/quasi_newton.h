// L-BFGS on the energy, for lambda = 1 on every term (docs/design.md §4, record 0070).
//
// There E(x) (rotations fitted to x) is what the plain local/global step descends, and its
// gradient is -2 A F with F = G(x) - x, so the plain step is the quasi-Newton step with the
// initial inverse Hessian H0 = (2A)^-1 (Liu et al. 2017, "Quasi-Newton methods for real-time
// simulation of hyperelastic materials", use the same H0). L-BFGS adds curvature from its
// last pairs, scales H0 by the newest pair (Shanno-Phua), and a line search on E takes the
// step: Armijo, and doubling while E keeps falling. Measured (record 0070): where a large
// edit passes through a region in which E curves downwards (J_G's modulus above 1 at the
// iterate), Anderson, a root finder, extrapolates uphill and its safeguard rejects every
// step (Spot 11.5k swung sideways: 0 of the last 1,600 taken); L-BFGS descends and converges.
//
// H0 costs no back-substitution: q = -grad - sum a_i y_i gives H0 q = F - sum a_i H0 y_i,
// and H0 y_i = -(F_{i+1} - F_i) is kept with the pair. An iteration whose first trial passes
// costs what a plain one does (one local fit, one global step, a sparse product with A).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "strategies/convergence.h"
#include "strategies/fixed_point_problem.h"
#include "base/iteration_point.h"
#include "base/solve_types.h"

namespace edgedeform {

struct QuasiNewtonSettings {
  int max_iterations = 2000;   // global steps
  double tolerance = 1e-3;     // of the diagonal (SolveOptions::tolerance)
  double diag = 1.0;           // rest bounding-box diagonal
  bool verify_claims = false;  // a claim is checked by Arnoldi on J_G first (claim_check.h)
};

// The strategy's state between calls: a warm solve with unchanged targets continues the
// pairs and the rate estimate.
class QuasiNewtonMemory {
 public:
  // Pairs kept (record 0070: 5 and 20 measured).
  static constexpr int kPairs = 5;

  // Starts afresh for `free_vertices` free vertices (new targets or a cold start).
  void restart(int free_vertices);
  // Another strategy moved the iterate: the pairs and the rate estimate no longer describe it.
  void forget();

 private:
  friend void quasi_newton_solve(FixedPointProblem&, const QuasiNewtonSettings&, IterationPoint&, LocalFit&,
                                 QuasiNewtonMemory&, SolveResult&);
  struct Pair {
    Eigen::MatrixXd s, y, h0y;  // step, gradient change, H0 times the gradient change
    double rho = 0.0;           // 1 / (s . y)
  };
  // Records the pair from the last point to y (gradient grad, F = G(y) - y) when its
  // curvature s . y is positive, then makes y the last point.
  void add_point(const Eigen::MatrixXd& y, const Eigen::MatrixXd& grad, const Eigen::MatrixXd& F);
  // out = the L-BFGS direction H (-grad) from the kept pairs.
  void direction(const Eigen::MatrixXd& grad, const Eigen::MatrixXd& F, Eigen::MatrixXd& out);
  void drop_pairs() { count_ = 0; next_ = 0; }

  std::vector<Pair> pairs_{kPairs};  // ring buffer
  int count_ = 0, next_ = 0;
  Eigen::MatrixXd last_y_, last_grad_, last_F_;
  bool has_last_ = false;
  std::vector<double> alpha_;           // two-loop scratch
  Eigen::MatrixXd g_, F_, grad_, d_;  // iteration scratch
  Eigen::MatrixXd z_;                 // the two-loop's q, then the line search's trial point
  Eigen::MatrixXd rhs_;
  LocalFit trial_, scratch_;            // the line search's fits
  ConvergenceMonitor monitor_;
};

// Runs until converged or max_iterations global steps (each iteration one global step; its
// line search's local fits beyond the first are counted in result.line_search_fits); fills
// result's iterations, energies, residuals, distance_estimate, converged, accelerated_steps
// (quasi-Newton steps taken) and rejected_steps (a direction that failed its line search:
// the plain step instead, the pairs dropped), and warnings. Throws SolveInterrupted when the
// problem asks to stop. On return point.y holds the result and fit its local fit.
void quasi_newton_solve(FixedPointProblem& problem, const QuasiNewtonSettings& settings, IterationPoint& point,
                        LocalFit& fit, QuasiNewtonMemory& memory, SolveResult& result);

}  // namespace edgedeform
