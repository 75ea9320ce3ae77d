// What an iteration strategy (plain/Anderson, Newton) needs of the deformation problem: the
// local fit, the global step, A and its factor, and the Newton matrix's factorization. The
// Deformer offers it over its system; the tests build their own.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "edgedeform/fixed_point_linearization.h"
#include "edgedeform/local_step.h"
#include "edgedeform/types.h"

namespace edgedeform {

class FixedPointProblem {
 public:
  virtual ~FixedPointProblem() = default;
  // fit := the local fit at free positions y (#free x 3); returns E(y). The node positions
  // of the last call are those linearize() and factor_newton() use.
  virtual double local_fit(const Eigen::MatrixXd& y, LocalFit& fit) = 0;
  // rhs := the global step's right side for `fit`, g := A^-1 rhs (= G(y) for fit = fit(y)).
  virtual void global_step(const LocalFit& fit, Eigen::MatrixXd& rhs, Eigen::MatrixXd& g) = 0;
  virtual void solve_A(const Eigen::MatrixXd& r, Eigen::MatrixXd& z) = 0;
  virtual const SparseMatrix& A() const = 0;
  // The linearization at the point of the last local_fit call, whose fit `fit` is.
  // With `projection` (lambda = 1 only): the terms below it projected (linearize_fit; 1: the
  // per-node positive model).
  virtual std::unique_ptr<FixedPointLinearization> linearize(const LocalFit& fit, double projection) = 0;
  // Assembles the Newton matrix K of that linearization and factors it (Cholesky, lambda = 1
  // on every term): false when K is not positive definite. Counts its time and factorizations in the solve's result.
  virtual bool factor_newton(const LocalFit& fit, double projection) = 0;
  // delta := K^-1 b (#free x 3) with the last factorization.
  virtual void solve_newton(const Eigen::MatrixXd& b, Eigen::MatrixXd& delta) = 0;
  // The Newton step delta at the point of the last local_fit call (`fit` its fit), lifted into
  // the fit: each term's rotation and scale moved along their linear response to delta.
  // lifted_step(alpha) is then the global step from R_t exp(alpha [omega_t]x), s_t + alpha
  // ds_t: G(y) + alpha J_G delta to first order, with a turning part's arc exact.
  virtual void prepare_lift(const LocalFit& fit, const Eigen::MatrixXd& delta) { (void)fit; (void)delta; }
  virtual void lifted_step(const LocalFit& fit, double alpha, Eigen::MatrixXd& out) {
    (void)fit; (void)alpha; (void)out;
  }
  // Asked between steps (and inside long steps): true stops the solve.
  virtual bool interrupt_requested() = 0;
};

}  // namespace edgedeform
