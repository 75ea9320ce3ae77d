#include "system/fixed_point_linearization.h"

namespace edgedeform {

FixedPointLinearization::FixedPointLinearization(const ConstrainedSystem& system, const AssembledSystem& assembled,
                                                 const LocalFit& fit, const RowMatrixX3d& node_positions)
    : system_(system),
      assembled_(assembled),
      fit_(fit),
      linearization_(linearize_fit(system.stencil, node_positions, fit)) {
  padded_.setZero(system.n_free() + system.n_fixed(), 3);  // fixed vertices never move
}

void FixedPointLinearization::rhs_derivative(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out) const {
  padded_.topRows(system_.n_free()) = dx;
  stencil_node_positions(system_, padded_, node_change_);
  differentiate_fit(system_.stencil, fit_, linearization_, node_change_, omega_, dscale_);
  assembled_.H.apply_derivative(fit_.rotation, fit_.scale, omega_, dscale_, out);
}

void FixedPointLinearization::k_product(const Eigen::MatrixXd& dx, Eigen::MatrixXd& out) const {
  rhs_derivative(dx, out);
  out = assembled_.A * dx - out;
}

}  // namespace edgedeform
