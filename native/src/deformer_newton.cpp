// Deformer's Newton-Krylov iteration and live predictor: the Deformer's one-step map, local
// fit and factor (Deformer::StepProblem) offered to newton_krylov_solve and coarse_predict,
// over the coarse space its CoarseCache keeps; and the inspection calls.
#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "edgedeform/deformer.h"
#include "edgedeform/mesh_checks.h"
#include "edgedeform/newton_krylov.h"

namespace edgedeform {

const CoarseBasis* Deformer::coarse_basis(int patches, int blend) {
  return coarse_.basis(*system_, rest_, topology_.edges, patches, blend);
}

bool Deformer::predict(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit, SolveResult& result) {
  const CoarseBasis* basis = coarse_basis(options.coarse_patches, options.coarse_blend);
  if (!basis) return false;
  Iteration& it = iter_;
  const PredictorOutcome outcome =
      coarse_predict(problem, *basis, coarse_.stiffness(assembled_->A), coarse_.predictor(), diag_, it.y, fit,
                     it.energy, result);
  ++result.predictions;
  if (outcome.kept) {
    ++result.predictions_kept;
    it.plain.monitor.require_full_window();  // its first ratios would be the fast modes'
  }
  result.coarse_dimension = basis->dimension();
  it.newton_valid = false;  // Newton's state was for other targets
  return true;
}

void Deformer::iterate_newton(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                              SolveResult& result) {
  Iteration& it = iter_;
  NewtonSettings settings;
  settings.max_iterations = options.max_iterations;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.descent = assembled_->term_lambda.size() > 0 && assembled_->term_lambda.minCoeff() >= 1.0;
  settings.krylov_iterations = options.krylov_iterations;
  // A solve that continues a fitted iterate (live editing standing still) goes on with the
  // last call's Newton state; a cold start or moved targets start afresh (the naive or
  // previous step, then a plain step).
  if (!it.continuable || !it.newton_valid) it.newton.reset(2, settings.descent);
  it.newton_valid = true;
  settings.coarse = coarse_basis(options.coarse_patches, options.coarse_blend);
  if (settings.coarse) {
    settings.coarse_stiffness = &coarse_.stiffness(assembled_->A);
    settings.coarse_correction = &coarse_.newton_correction();
    result.coarse_dimension = settings.coarse->dimension();
  }
  result.energies.reserve(static_cast<size_t>(options.max_iterations));
  result.residuals.reserve(static_cast<size_t>(options.max_iterations));
  // The Anderson state and rate estimate do not describe Newton's iterates.
  it.plain.forget();
  newton_krylov_solve(problem, settings, IterationPoint{it.y, fit, it.energy, it.continuable, it.newton}, result);
}

void Deformer::iterate_direct(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                              SolveResult& result) {
  Iteration& it = iter_;
  const bool descent = assembled_->term_lambda.size() > 0 && assembled_->term_lambda.minCoeff() >= 1.0;
  const bool fresh = !it.continuable || !it.direct_valid;
  it.newton_valid = false;
  if (fresh && options.newton.lead_in > 0) {  // an Anderson lead-in
    PlainAndersonSettings lead;
    lead.max_iterations = std::min(options.newton.lead_in, options.max_iterations);
    lead.tolerance = options.tolerance;
    lead.diag = diag_;
    lead.descent = descent;
    const size_t warnings = result.warnings.size();
    plain_anderson_solve(problem, lead, PlainAndersonPoint{it.y, fit, it.energy, it.continuable, it.plain}, result);
    if (result.converged || result.iterations >= options.max_iterations) {
      it.direct_valid = false;
      return;
    }
    result.warnings.resize(warnings);  // its "not converged" is not the solve's
  }
  if (fresh) it.direct.reset(it.continuable ? 0 : 1, options.newton.start_level);
  it.direct_valid = true;
  it.plain.forget();  // the Anderson state and rate estimate do not describe Newton's iterates
  DirectNewtonSettings settings;
  settings.max_iterations = options.max_iterations;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.descent = descent && !std::getenv("EDGEDEFORM_DN_RESIDUAL");  // EXPERIMENT
  settings.start_level = options.newton.start_level;
  settings.correction = options.newton.correction;
  settings.extrapolate = options.newton.extrapolate;
  settings.level_patience = options.newton.level_patience;
  settings.ladder = options.newton.ladder;
  result.energies.reserve(static_cast<size_t>(options.max_iterations));
  result.residuals.reserve(static_cast<size_t>(options.max_iterations));
  direct_newton_solve(problem, settings, DirectNewtonPoint{it.y, fit, it.energy, it.continuable, it.direct}, result);
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

SparseMatrix Deformer::coarse_basis_matrix(int patches, int blend) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!system_) throw std::invalid_argument("set_constraints(handles=...) must be called first");
  if (patches < 1) throw std::invalid_argument("patches must be at least 1");
  const CoarseBasis* b = coarse_basis(patches, blend);
  if (!b) return SparseMatrix(3 * system_->n_free(), 0);
  return edgedeform::coarse_basis_matrix(*b);
}

SparseMatrix Deformer::coarse_operator_at(const RowMatrixX3d& X, int patches, int blend) {
  std::lock_guard<std::mutex> lock(mutex_);
  RowMatrixX3d x_local;
  LocalFit fit;
  prepare_point(X, x_local, fit);
  if (patches < 1) throw std::invalid_argument("patches must be at least 1");
  const CoarseBasis* b = coarse_basis(patches, blend);
  if (!b) return SparseMatrix(0, 0);
  const FixedPointLinearization lin(*system_, *assembled_, fit, node_positions_);
  return coarse_operator(*b, coarse_.stiffness(assembled_->A), lin);
}

}  // namespace edgedeform
