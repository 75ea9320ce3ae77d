// The one-step map G(x) = A^-1 (rhs(fit(x))) linearized at a point (docs/design.md §4, "Reaching
// the fixed point"): the right side's derivative D = d rhs / dx (the local fit's derivative,
// then the rotation operator's), K = A - D = A (I - J_G), and
// J_G = A^-1 D. At lambda = 1 on every term K is the energy's Hessian (halved) at the fitted
// rotations. Vectors are free-vertex displacements, (#free x 3).
#pragma once

#include "system/constrained_system.h"
#include "local_fit/local_fit_derivative.h"

namespace edgedeform {

class FixedPointLinearization {
 public:
  // `fit` is the local fit at node positions `node_positions` (stencil_node_positions of
  // the point); the system, its operators and the fit must outlive this object.
  FixedPointLinearization(const ConstrainedSystem& system, const AssembledSystem& assembled, const LocalFit& fit,
                          const RowMatrixX3d& node_positions);

  // out = D dx.
  void rhs_derivative(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out) const;
  // out = K dx = A dx - D dx.
  void k_product(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out) const;

 private:
  const ConstrainedSystem& system_;
  const AssembledSystem& assembled_;
  const LocalFit& fit_;
  FitLinearization linearization_;
  // Scratch of one product (a product is not re-entrant).
  mutable RowMatrixX3d padded_, node_change_, omega_;
  mutable Eigen::VectorXd dscale_;
};

}  // namespace edgedeform
