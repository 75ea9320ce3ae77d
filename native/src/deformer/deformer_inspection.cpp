// The Deformer's inspection calls: the one-step map G and its derivative at a given shape
// (tests, bench/soft_modes.py).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "deformer/deformer.h"
#include "mesh/mesh_checks.h"

namespace edgedeform {

const std::vector<int>& Deformer::free_vertices() const {
  if (!system_) throw std::invalid_argument("set_constraints(handles=...) must be called first");
  return system_->free_vertices;
}

Eigen::MatrixXd Deformer::prepare_point(const RowMatrixX3d& X, RowMatrixX3d& x_local, LocalFit& fit) {
  if (!system_) throw std::invalid_argument("set_constraints(handles=...) must be called first");
  if (X.rows() != rest_.rows())
    throw std::invalid_argument("X has " + std::to_string(X.rows()) + " rows, expected " + std::to_string(rest_.rows()));
  check_finite(X, "X");
  SolveResult scratch;
  ensure_factored(scratch);
  const ConstrainedSystem& sys = *system_;
  const int nf = sys.n_free(), nc = sys.n_fixed();
  x_local.resize(nf + nc, 3);
  for (int k = 0; k < nf; ++k) x_local.row(k) = X.row(sys.free_vertices[static_cast<size_t>(k)]);
  for (int k = 0; k < nc; ++k) x_local.row(nf + k) = X.row(sys.fixed_vertices[static_cast<size_t>(k)]);
  const Eigen::MatrixXd y = x_local.topRows(nf);
  local_step(y, x_local, fit, scratch);
  return -(assembled_->K_fixed * x_local.bottomRows(nc));
}

Eigen::MatrixXd Deformer::one_step_map(const RowMatrixX3d& X) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  const Eigen::MatrixXd c = prepare_point(X, x_local, fit);
  Eigen::MatrixXd rhs, g;
  assembled_->H.apply(fit.rotation, fit.scale, c, rhs);
  factors_.factor().solve(rhs, g);
  return g;
}

LocalFit Deformer::local_fit_at(const RowMatrixX3d& X) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  prepare_point(X, x_local, fit);
  return fit;
}

Eigen::MatrixXd Deformer::global_step_with(const RowMatrixX3d& X, const std::vector<Eigen::Matrix3d>& rotation,
                                           const Eigen::VectorXd& scale) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  const Eigen::MatrixXd c = prepare_point(X, x_local, fit);
  if (rotation.size() != fit.rotation.size() || scale.size() != fit.scale.size())
    throw std::invalid_argument("expected " + std::to_string(fit.rotation.size()) + " rotations and scales, got " +
                                std::to_string(rotation.size()) + " and " + std::to_string(scale.size()));
  for (const Eigen::Matrix3d& R : rotation)
    if (!R.allFinite()) throw std::invalid_argument("rotations must be finite");
  if (!scale.allFinite()) throw std::invalid_argument("scales must be finite");
  Eigen::MatrixXd rhs, g;
  assembled_->H.apply(rotation, scale, c, rhs);
  factors_.factor().solve(rhs, g);
  return g;
}

Eigen::MatrixXd Deformer::jacobian_product(const RowMatrixX3d& X, const Eigen::MatrixXd& dX, bool k_product) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  prepare_point(X, x_local, fit);
  if (dX.rows() != system_->n_free() || dX.cols() != 3)
    throw std::invalid_argument("dX must be (#free vertices, 3) = (" + std::to_string(system_->n_free()) + ", 3)");
  const FixedPointLinearization lin(*system_, *assembled_, fit, node_positions_);
  Eigen::MatrixXd out;
  if (k_product) {
    lin.k_product(dX, out);
    return out;
  }
  Eigen::MatrixXd d_rhs;
  lin.rhs_derivative(dX, d_rhs);
  factors_.factor().solve(d_rhs, out);
  return out;
}

}  // namespace edgedeform
