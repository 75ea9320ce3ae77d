// What an iteration strategy (plain/Anderson, L-BFGS) needs of the deformation problem: the
// local fit, the global step, A and its factor, and the one-step map's linearization (the
// claim check's). The Deformer offers it over its system; the tests build their own.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "system/fixed_point_linearization.h"
#include "local_fit/local_step.h"
#include "base/types.h"

namespace edgedeform {

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
  // Asked between steps (and inside long steps): true stops the solve.
  virtual bool interrupt_requested() = 0;
};

}  // namespace edgedeform
