#include "edgedeform/deformer.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "edgedeform/errors.h"
#include "edgedeform/mesh_checks.h"
#include "edgedeform/stiffness.h"

namespace edgedeform {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Positions of the stencil nodes from the local vertex positions (free, then fixed).
void stencil_node_positions(const ConstrainedSystem& sys, const RowMatrixX3d& x_local, RowMatrixX3d& p) {
  const Eigen::Index n = sys.stencil_node_vertices.rows();
  p.resize(n, 3);
  for (Eigen::Index s = 0; s < n; ++s)
    p.row(s) = 0.5 * (x_local.row(sys.stencil_node_vertices(s, 0)) + x_local.row(sys.stencil_node_vertices(s, 1)));
}

void check_solve_arguments(const ConstrainedSystem& sys, int n, const RowMatrixX3d& targets, const SolveOptions& o,
                           const SafeRange& range) {
  if (targets.rows() != static_cast<Eigen::Index>(sys.handles.size()))
    throw std::invalid_argument("targets has " + std::to_string(targets.rows()) + " rows, expected one per handle (" +
                                std::to_string(sys.handles.size()) + ")");
  check_finite(targets, "targets");
  check_distance(targets, range.center, range.limit, "targets");
  if (o.max_iterations < 1)
    throw std::invalid_argument("max_iterations must be at least 1, got " + std::to_string(o.max_iterations));
  if (!(o.tolerance >= 0.0) || !std::isfinite(o.tolerance))
    throw std::invalid_argument("tolerance must be a finite number >= 0");
  if (o.initial) {
    if (o.initial->rows() != n)
      throw std::invalid_argument("initial has " + std::to_string(o.initial->rows()) + " rows, expected " +
                                  std::to_string(n) + " (one per vertex)");
    check_finite(*o.initial, "initial");
    check_distance(*o.initial, range.center, range.limit, "initial");
  }
}

void stop_if_interrupted(const SolveOptions& o) {
  if (o.interrupt_requested && o.interrupt_requested()) throw SolveInterrupted("solve interrupted");
}

}  // namespace

Deformer::Deformer(const RowMatrixX3d& V, const RowMatrixX3i& F, Domain domain, bool clamp_negative_weights) {
  check_mesh(V, F);
  safe_range_.center = 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
  check_distance(V, safe_range_.center, largest_safe_distance(1.0), "V");  // before any products
  check_geometry(V, F);
  rest_ = V;
  faces_ = F;
  topology_ = build_edge_topology(F, static_cast<int>(V.rows()));
  graph_ = build_node_graph(V, F, topology_, domain, clamp_negative_weights);
  safe_range_.limit = largest_safe_distance(graph_.arc_weights.cwiseAbs().sum());
  check_distance(V, safe_range_.center, safe_range_.limit, "V");
  referenced_ = referenced_vertices(F, static_cast<int>(V.rows()));
  seams_ = find_seam_copies(V, F);
  seam_tolerance_ = 1e-6 * (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  vertex_lambda_ = Eigen::VectorXd::Constant(V.rows(), 0.5);
  node_lambda_ = node_stiffness(graph_, vertex_lambda_);
  node_rotation_.assign(static_cast<size_t>(graph_.n_nodes), Eigen::Matrix3d::Identity());
  node_right_vectors_ = node_rotation_;
  node_scale_ = Eigen::VectorXd::Ones(graph_.n_nodes);
}

void Deformer::set_constraints(const ConstraintSets& sets) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto system = std::make_unique<ConstrainedSystem>(
      build_constrained_system(graph_, rest_, topology_.edges, referenced_, sets));
  keep_last_fit_per_node();
  system_ = std::move(system);
  assembled_.reset();
}

void Deformer::keep_last_fit_per_node() {
  if (!last_fit_valid_) return;
  const std::vector<int>& nodes = system_->term_nodes;
  for (size_t t = 0; t < nodes.size(); ++t) {
    const auto i = static_cast<size_t>(nodes[t]);
    node_rotation_[i] = last_fit_.rotation[t];
    node_right_vectors_[i] = last_fit_.right_vectors[t];
    node_scale_(nodes[t]) = last_fit_.scale(static_cast<Eigen::Index>(t));
  }
  has_previous_ = true;
  last_fit_valid_ = false;
}

LocalFit Deformer::starting_fit(const SolveOptions& options) {
  const ConstrainedSystem& sys = *system_;
  const auto T = static_cast<size_t>(sys.n_terms());
  LocalFit fit;
  if (options.warm_start && !options.initial && last_fit_valid_) {  // live editing: no copies
    last_fit_valid_ = false;
    return std::move(last_fit_);
  }
  // A cold start (or an initial shape) begins every SVD at V = I, so that it does not depend
  // on what this Deformer solved before.
  fit.rotation.assign(T, Eigen::Matrix3d::Identity());
  fit.right_vectors.assign(T, Eigen::Matrix3d::Identity());
  fit.scale = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(T));
  if (options.warm_start && !options.initial && has_previous_)  // constraints changed since
    for (size_t t = 0; t < T; ++t) {
      const auto i = static_cast<size_t>(sys.term_nodes[t]);
      fit.rotation[t] = node_rotation_[i];
      fit.right_vectors[t] = node_right_vectors_[i];
      fit.scale(static_cast<Eigen::Index>(t)) = node_scale_(sys.term_nodes[t]);
    }
  return fit;
}

void Deformer::set_stiffness(double lambda) {
  if (!(lambda >= 0.0 && lambda <= 1.0))
    throw std::invalid_argument("stiffness " + std::to_string(lambda) + " is outside [0, 1]");
  set_stiffness(Eigen::VectorXd::Constant(rest_.rows(), lambda));
}

void Deformer::set_stiffness(const Eigen::VectorXd& vertex_lambda) {
  std::lock_guard<std::mutex> lock(mutex_);
  check_stiffness(vertex_lambda, n_vertices());
  Eigen::VectorXd node = node_stiffness(graph_, vertex_lambda);
  vertex_lambda_ = vertex_lambda;
  if (node == node_lambda_) return;  // the same system: keep the factorization
  node_lambda_ = std::move(node);
  stiffness_changed_ = true;
}

void Deformer::ensure_factored(SolveResult& result) {
  if (assembled_ && !stiffness_changed_) return;
  const auto start = Clock::now();
  // Kept only once factored: after a failure the next call assembles anew.
  std::unique_ptr<AssembledSystem> assembled = std::move(assembled_);
  if (assembled)  // only lambda changed: new values in the same operators and pattern
    update_stiffness(*assembled, *system_, node_lambda_);
  else
    assembled = std::make_unique<AssembledSystem>(assemble_system(*system_, node_lambda_));
  if (system_->n_free() > 0) {
    const std::vector<int> order = free_vertex_order(*system_, vertex_rank_);
    cholesky_.factorize(assembled->A, order);  // throws FactorizationError
    if (order.empty()) remember_order();
  }
  assembled_ = std::move(assembled);
  stiffness_changed_ = false;
  result.factor_ms = ms_since(start);
}

void Deformer::remember_order() {
  const std::vector<int> order = cholesky_.order();
  vertex_rank_.assign(static_cast<size_t>(n_vertices()), -1);
  for (size_t k = 0; k < order.size(); ++k)
    vertex_rank_[static_cast<size_t>(system_->free_vertices[static_cast<size_t>(order[k])])] = static_cast<int>(k);
}

SolveResult Deformer::solve(const RowMatrixX3d& targets, const SolveOptions& options) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!system_) throw std::invalid_argument("set_constraints(handles=...) must be called before solve");
  const ConstrainedSystem& sys = *system_;
  check_solve_arguments(sys, n_vertices(), targets, options, safe_range_);

  SolveResult result;
  result.warnings = sys.warnings;
  result.free_vertices = sys.n_free();
  result.active_nodes = sys.n_terms();
  ensure_factored(result);
  const AssembledSystem& as = *assembled_;

  // Every vertex at its constraint: handles on their targets, the rest at rest.
  RowMatrixX3d& constrained = result.positions;  // free rows are overwritten at the end
  constrained = rest_;
  for (size_t h = 0; h < sys.handles.size(); ++h) constrained.row(sys.handles[h]) = targets.row(static_cast<Eigen::Index>(h));
  const int nf = sys.n_free(), nc = sys.n_fixed();
  if (nf == 0) {
    result.converged = true;
    return result;
  }

  RowMatrixX3d x_local(nf + nc, 3);
  for (int k = 0; k < nc; ++k) x_local.row(nf + k) = constrained.row(sys.fixed_vertices[static_cast<size_t>(k)]);
  const Eigen::MatrixXd c = -(as.K_fixed * x_local.bottomRows(nc));  // the fixed vertices' share

  // Rotations and scales of the first global step.
  LocalFit fit = starting_fit(options);
  RowMatrixX3d p;
  if (options.initial) {
    for (int k = 0; k < nf; ++k) x_local.row(k) = options.initial->row(sys.free_vertices[static_cast<size_t>(k)]);
    stencil_node_positions(sys, x_local, p);
    fit_local(sys.stencil, p, as.term_lambda, fit);
    result.initial_energy = fit.energy;
  }

  // Below this the energy is round-off of a shape that is already at rest (or rigidly moved).
  const double energy_floor = 1e-14 * sys.rest_scale;
  Eigen::MatrixXd rhs, xf;
  for (int it = 0; it < options.max_iterations; ++it) {
    stop_if_interrupted(options);
    auto t0 = Clock::now();
    as.H.apply(fit.rotation, fit.scale, c, rhs);
    result.rhs_ms += ms_since(t0);

    t0 = Clock::now();
    cholesky_.solve(rhs, xf);
    x_local.topRows(nf) = xf;
    result.solve_ms += ms_since(t0);

    t0 = Clock::now();
    stencil_node_positions(sys, x_local, p);
    fit_local(sys.stencil, p, as.term_lambda, fit);
    result.local_ms += ms_since(t0);

    result.energies.push_back(fit.energy);
    ++result.iterations;
    const std::optional<double> previous =
        it > 0 ? std::optional<double>(result.energies[static_cast<size_t>(it) - 1]) : result.initial_energy;
    if (previous && std::abs(fit.energy - *previous) <= options.tolerance * std::max(fit.energy, energy_floor)) {
      result.converged = true;
      break;
    }
  }

  for (int k = 0; k < nf; ++k) result.positions.row(sys.free_vertices[static_cast<size_t>(k)]) = x_local.row(k);
  if (auto torn = seam_warning(seams_, result.positions, seam_tolerance_)) result.warnings.push_back(*torn);
  last_fit_ = std::move(fit);  // the next warm start begins here
  last_fit_valid_ = true;
  return result;
}

double Deformer::energy(const RowMatrixX3d& X) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (X.rows() != rest_.rows())
    throw std::invalid_argument("X has " + std::to_string(X.rows()) + " rows, expected " + std::to_string(rest_.rows()));
  check_finite(X, "X");
  if (!full_stencil_) {
    std::vector<int> all(static_cast<size_t>(graph_.n_nodes));
    for (int i = 0; i < graph_.n_nodes; ++i) all[static_cast<size_t>(i)] = i;
    full_stencil_ = std::make_unique<NodeStencil>(build_stencil(graph_, graph_.node_positions(rest_), all, all));
  }
  LocalFit fit;
  fit_local(*full_stencil_, graph_.node_positions(X), node_lambda_, fit);
  return fit.energy;
}

}  // namespace edgedeform
