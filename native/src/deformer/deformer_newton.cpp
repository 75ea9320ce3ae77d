// Deformer's strategies (plain/Anderson, and Newton after its Anderson lead-in) run on its
// StepProblem, and the inspection calls of the one-step map and its derivative.
#include <algorithm>
#include <stdexcept>
#include <string>

#include "edgedeform/deformer.h"
#include "edgedeform/mesh_checks.h"
#include "edgedeform/newton_matrix.h"

namespace edgedeform {

void Deformer::iterate_plain_anderson(FixedPointProblem& problem, const SolveOptions& options, int budget, LocalFit& fit,
                                      SolveResult& result) {
  iter_.newton_valid = false;  // Newton's state no longer describes the iterate
  PlainAndersonSettings settings;
  settings.max_iterations = budget;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.descent = all_rigid_;
  settings.accelerate = options.acceleration != Acceleration::None;
  settings.verify_claims = options.verify_claims;
  plain_anderson_solve(problem, settings, iter_.point, fit, iter_.plain, result);
}

void Deformer::iterate_newton(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                              SolveResult& result) {
  if (!all_rigid_) {
    // Newton steps only where lambda = 1 on every term; below it Anderson won every
    // measurement, and the LU Newton failed on the koala (docs/decisions/0029).
    iterate_plain_anderson(problem, options, options.max_iterations, fit, result);
    return;
  }
  IterationState& it = iter_;
  const int lead_in_left = options.newton.lead_in - it.lead_in_iterations;
  if (!it.newton_valid && lead_in_left > 0) {
    // The Anderson lead-in, counted since the targets were set (live ticks share it); its
    // "not converged" at the end of the lead-in is not the solve's.
    const size_t warnings = result.warnings.size();
    const int before = result.iterations;
    iterate_plain_anderson(problem, options, std::min(lead_in_left, options.max_iterations), fit, result);
    it.lead_in_iterations += result.iterations - before;
    if (result.converged || result.iterations >= options.max_iterations) return;
    result.warnings.resize(warnings);
  }
  const bool fresh = !it.point.fitted || !it.newton_valid;
  // A solve that continues a fitted iterate (live editing standing still) goes on with the
  // last call's Newton state; a fresh start takes a plain step first when the fit is not y's.
  if (fresh) it.newton.reset(it.point.fitted ? 0 : 1);
  if (fresh && !options.newton.ladder) it.newton.level = 0;  // "full": K itself first
  it.newton_valid = true;
  it.plain.forget();  // the Anderson state and rate estimate do not describe Newton's iterates
  NewtonSettings settings;
  settings.max_iterations = options.max_iterations;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.ladder = options.newton.ladder;
  settings.lifted = options.newton.lifted;
  result.energies.reserve(static_cast<size_t>(options.max_iterations));
  result.residuals.reserve(static_cast<size_t>(options.max_iterations));
  const NewtonEnd end =
      projected_newton_solve(problem, settings, it.point, fit, it.newton, result);
  if (end == NewtonEnd::GaveUp && result.iterations < options.max_iterations) {
    // Newton's steps stopped lowering the merit: Anderson for the rest of the budget.
    ++result.newton_fallbacks;
    it.plain.restart(static_cast<int>(it.point.y.rows()), options.anderson_window);
    iterate_plain_anderson(problem, options, options.max_iterations - result.iterations, fit, result);
  }
}

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

Eigen::MatrixXd Deformer::jacobian_product(const RowMatrixX3d& X, const Eigen::MatrixXd& dX, bool newton_operator) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  prepare_point(X, x_local, fit);
  if (dX.rows() != system_->n_free() || dX.cols() != 3)
    throw std::invalid_argument("dX must be (#free vertices, 3) = (" + std::to_string(system_->n_free()) + ", 3)");
  const FixedPointLinearization lin(*system_, *assembled_, fit, node_positions_);
  Eigen::MatrixXd out;
  if (newton_operator) {
    lin.newton_operator(dX, out);
    return out;
  }
  Eigen::MatrixXd d_rhs;
  lin.rhs_derivative(dX, d_rhs);
  factors_.factor().solve(d_rhs, out);
  return out;
}

SparseMatrix Deformer::newton_matrix_at(const RowMatrixX3d& X, double projection) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!(projection >= 0.0 && projection <= 1.0)) throw std::invalid_argument("projection must be in [0, 1]");
  RowMatrixX3d x_local;
  LocalFit fit;
  prepare_point(X, x_local, fit);
  const FixedPointLinearization lin(*system_, *assembled_, fit, node_positions_, projection);
  NewtonMatrix K(*system_, *assembled_);
  K.assemble(lin);
  return SparseMatrix(K.transpose().transpose());
}

}  // namespace edgedeform
