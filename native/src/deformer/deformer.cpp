#include "deformer/deformer.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "mesh/cotangent.h"
#include "base/errors.h"
#include "strategies/fixed_point_iteration.h"
#include "local_fit/local_fit_derivative.h"
#include "strategies/quasi_newton.h"
#include "mesh/mesh_checks.h"
#include "mesh/region_graph.h"
#include "mesh/stiffness.h"

namespace edgedeform {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void check_solve_arguments(const ConstrainedSystem& sys, int n, const RowMatrixX3d& targets, const SolveOptions& o,
                           const SafeRange& range) {
  if (targets.rows() != static_cast<Eigen::Index>(sys.handles.size()))
    throw std::invalid_argument("targets has " + std::to_string(targets.rows()) + " rows, expected one per handle (" +
                                std::to_string(sys.handles.size()) + ")");
  check_finite(targets, "targets");
  check_distance(targets, range.center, range.limit, "targets");
  check_in_range(kAndersonWindowRange, o.anderson_window);
  check_in_range(kMaxIterationsRange, o.max_iterations);
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

// Sum over every corner of |1/2 cot|: at least the sum of |arc weight| over the graph of either
// domain (an arc adds up its corners), so the safe range it gives is no wider than the graph's,
// and it needs no graph.
double total_corner_weight(const RowMatrixX3d& V, const RowMatrixX3i& F) {
  double total = 0.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = V.row(F(f, k)).transpose();
      total += std::abs(0.5 * safe_cotangent(V.row(F(f, (k + 1) % 3)).transpose() - a,
                                             V.row(F(f, (k + 2) % 3)).transpose() - a));
    }
  return total;
}

}  // namespace

Deformer::Deformer(const RowMatrixX3d& V, const RowMatrixX3i& F, Domain domain, bool clamp_negative_weights)
    : domain_(domain), clamp_negative_weights_(clamp_negative_weights) {
  check_mesh(V, F);
  safe_range_.center = 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
  check_distance(V, safe_range_.center, largest_safe_distance(1.0), "V");  // before any products
  check_geometry(V, F);
  rest_ = V;
  faces_ = F;
  incidence_ = mesh_incidence(F, static_cast<int>(V.rows()));
  safe_range_.limit = largest_safe_distance(total_corner_weight(V, F));
  check_distance(V, safe_range_.center, safe_range_.limit, "V");
  referenced_ = referenced_vertices(F, static_cast<int>(V.rows()));
  seams_ = find_seam_copies(V, F);
  seam_tolerance_ = 1e-6 * (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  vertex_lambda_ = Eigen::VectorXd::Constant(V.rows(), 0.5);
  // Over the vertices the faces use: stray vertices never move and should not set the scale.
  Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (referenced_[static_cast<size_t>(v)]) {
      lo = lo.cwiseMin(V.row(v));
      hi = hi.cwiseMax(V.row(v));
    }
  diag_ = (hi - lo).norm();
  if (!(diag_ > 0.0) || !std::isfinite(diag_)) diag_ = 1.0;  // a single point: absolute units
}

void Deformer::set_constraints(const ConstraintSets& sets) {
  std::lock_guard<std::mutex> lock(mutex_);
  // The layout validates the sets before anything changes.
  std::shared_ptr<const ConstrainedSystem> system =
      operators_.set_system(layout(vertex_roles(rest_, neighbours(), referenced_, sets), sets));
  if (system_) warm_.keep_per_node(system_->term_nodes);  // while the old terms are known
  system_ = std::move(system);
  assembled_.reset();
  iter_.free_set_changed();
}

void Deformer::set_stiffness(double lambda) {
  if (!(lambda >= 0.0 && lambda <= 1.0))
    throw std::invalid_argument("stiffness " + std::to_string(lambda) + " is outside [0, 1]");
  set_stiffness(Eigen::VectorXd::Constant(rest_.rows(), lambda));
}

void Deformer::set_stiffness(const Eigen::VectorXd& vertex_lambda) {
  std::lock_guard<std::mutex> lock(mutex_);
  check_stiffness(vertex_lambda, n_vertices());
  if (vertex_lambda == vertex_lambda_) return;  // the same system: keep the factorization
  vertex_lambda_ = vertex_lambda;
  stiffness_changed_ = true;
}

void Deformer::ensure_factored(SolveResult& result) {
  if (assembled_ && !stiffness_changed_) return;
  const auto start = Clock::now();
  assembled_.reset();  // kept only once factored
  std::shared_ptr<const AssembledSystem> assembled = operators_.operators_for(*system_, vertex_lambda_);
  if (system_->n_free() > 0)
    factors_.factor_for(*system_, *assembled, operators_.is_base(assembled), operators_.base_values());
  assembled_ = std::move(assembled);
  stiffness_changed_ = false;
  all_rigid_ = assembled_->term_lambda.size() > 0 && assembled_->term_lambda.minCoeff() >= 1.0;
  iter_.system_changed();
  result.factor_ms = ms_since(start);
}

struct Deformer::StepProblem final : FixedPointProblem {
  Deformer& d;
  const Eigen::MatrixXd& c;  // the fixed vertices' share of the right side
  RowMatrixX3d& x_local;
  SolveResult& result;
  const SolveOptions& options;
  StepProblem(Deformer& deformer, const Eigen::MatrixXd& fixed_share, RowMatrixX3d& local, SolveResult& r,
              const SolveOptions& o)
      : d(deformer), c(fixed_share), x_local(local), result(r), options(o) {}
  double local_fit(const Eigen::MatrixXd& y, LocalFit& fit) override {
    d.local_step(y, x_local, fit, result);
    return fit.energy;
  }
  void global_step(const LocalFit& fit, Eigen::MatrixXd& rhs, Eigen::MatrixXd& g) override {
    auto t0 = Clock::now();
    d.assembled_->H.apply(fit.rotation, fit.scale, c, rhs, d.rhs_term_weights_);
    result.rhs_ms += ms_since(t0);
    t0 = Clock::now();
    d.factors_.factor().solve(rhs, g);
    result.solve_ms += ms_since(t0);
  }
  void solve_A(const Eigen::MatrixXd& r, Eigen::MatrixXd& z) override {
    const auto t0 = Clock::now();
    d.factors_.factor().solve(r, z);
    result.solve_ms += ms_since(t0);
  }
  const SparseMatrix& A() const override { return d.assembled_->A; }
  std::unique_ptr<FixedPointLinearization> linearize(const LocalFit& fit) override {
    return std::make_unique<FixedPointLinearization>(*d.system_, *d.assembled_, fit, d.node_positions_);
  }
  bool interrupt_requested() override { return options.interrupt_requested && options.interrupt_requested(); }
};

Acceleration Deformer::strategy_for(Acceleration asked) const {
  if (asked == Acceleration::Automatic || asked == Acceleration::Lbfgs)
    return all_rigid_ ? Acceleration::Lbfgs : Acceleration::Anderson;
  return asked;
}

void Deformer::iterate_plain_anderson(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                                      SolveResult& result) {
  IterationState& it = iter_;
  if (it.last_method == Acceleration::Lbfgs) it.plain.forget();  // its rate estimate saw other iterates
  it.last_method = options.acceleration == Acceleration::None ? Acceleration::None : Acceleration::Anderson;
  PlainAndersonSettings settings;
  settings.max_iterations = options.max_iterations;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.descent = all_rigid_;
  settings.accelerate = options.acceleration != Acceleration::None;
  settings.verify_claims = options.verify_claims;
  plain_anderson_solve(problem, settings, it.point, fit, it.plain, result);
}

void Deformer::iterate_quasi_newton(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                                    SolveResult& result) {
  IterationState& it = iter_;
  if (it.last_method != Acceleration::Lbfgs && it.last_method != Acceleration::Automatic)
    it.quasi_newton.forget();  // Anderson or plain steps moved the point
  it.last_method = Acceleration::Lbfgs;
  QuasiNewtonSettings settings;
  settings.max_iterations = options.max_iterations;
  settings.tolerance = options.tolerance;
  settings.diag = diag_;
  settings.verify_claims = options.verify_claims;
  quasi_newton_solve(problem, settings, it.point, fit, it.quasi_newton, result);
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

  LocalFit fit = start_point(targets, options, x_local, result);
  StepProblem problem(*this, c, x_local, result, options);
  const Acceleration method = strategy_for(options.acceleration);
  result.method = acceleration_name(method);
  if (options.acceleration == Acceleration::Lbfgs && method != Acceleration::Lbfgs)
    result.warnings.push_back("acceleration \"lbfgs\" descends the energy, which exists only where lambda = 1 on every "
                              "vertex; ran \"anderson\" instead");
  try {
    if (method == Acceleration::Lbfgs)
      iterate_quasi_newton(problem, options, fit, result);
    else
      iterate_plain_anderson(problem, options, fit, result);
  } catch (const SolveInterrupted&) {
    iter_.interrupted();
    throw;
  }

  const Eigen::MatrixXd& y = iter_.point.y;
  for (int k = 0; k < nf; ++k) result.positions.row(sys.free_vertices[static_cast<size_t>(k)]) = y.row(k);
  iter_.finished();
  if (auto torn = seam_warning(seams_, result.positions, seam_tolerance_)) result.warnings.push_back(*torn);
  warm_.store(std::move(fit));  // the next warm start begins here
  return result;
}

LocalFit Deformer::start_point(const RowMatrixX3d& targets, const SolveOptions& options, RowMatrixX3d& x_local,
                               SolveResult& result) {
  const ConstrainedSystem& sys = *system_;
  // Continue the last iteration (its Anderson history and rate estimate included) when
  // nothing changed; otherwise start afresh from rotations and scales (starting_fit).
  const bool warm = options.warm_start && !options.initial;
  const bool resume = warm && iter_.continues(targets) && warm_.has_fit();
  LocalFit fit = warm_.starting_fit(sys, warm);
  if (!resume)
    iter_.restart(targets, rest_, sys.free_vertices, options.warm_start, options.anderson_window);
  else
    iter_.plain.set_window(sys.n_free(), options.anderson_window);
  if (options.initial) {
    iter_.start_at(*options.initial, sys.free_vertices);
    IterationPoint& point = iter_.point;
    local_step(point.y, x_local, fit, result);
    result.initial_energy = fit.energy;
    point.energy = fit.energy;
    point.fitted = true;
  }
  return fit;
}

void Deformer::local_step(const Eigen::MatrixXd& y, RowMatrixX3d& x_local, LocalFit& fit, SolveResult& result) {
  const auto t0 = Clock::now();
  x_local.topRows(y.rows()) = y;
  stencil_node_positions(*system_, x_local, node_positions_);
  fit_local(system_->stencil, node_positions_, assembled_->term_lambda, fit, assembled_->term_similar);
  result.local_ms += ms_since(t0);
}

double Deformer::energy(const RowMatrixX3d& X) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (X.rows() != rest_.rows())
    throw std::invalid_argument("X has " + std::to_string(X.rows()) + " rows, expected " + std::to_string(rest_.rows()));
  check_finite(X, "X");
  const NodeGraph& graph = whole().graph;
  if (!full_stencil_) {
    std::vector<int> all(static_cast<size_t>(graph.n_nodes));
    for (int i = 0; i < graph.n_nodes; ++i) all[static_cast<size_t>(i)] = i;
    full_stencil_ = std::make_unique<NodeStencil>(build_stencil(graph, rest_, all, all));
  }
  const Eigen::VectorXd node_lambda = node_stiffness(graph, vertex_lambda_);
  LocalFit fit;
  fit_local(*full_stencil_, graph.node_positions(X), node_lambda, fit,
            similarity_share(node_lambda, similarity_floor(domain_)));
  return fit.energy;
}

Eigen::VectorXd Deformer::node_lambda() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return node_stiffness(whole().graph, vertex_lambda_);
}

const Deformer::WholeGraph& Deformer::whole() const {
  std::lock_guard<std::mutex> lock(whole_mutex_);
  if (!whole_) {
    auto built = std::make_unique<WholeGraph>();
    built->topology = build_edge_topology(faces_, n_vertices());
    built->graph = build_node_graph(rest_, faces_, built->topology, domain_, clamp_negative_weights_);
    whole_ = std::move(built);
  }
  return *whole_;
}

bool Deformer::whole_graph_built() const {
  std::lock_guard<std::mutex> lock(whole_mutex_);
  return whole_ != nullptr;
}

ConstrainedSystem Deformer::layout(VertexRoles roles, const ConstraintSets& sets) const {
  if (!whole_graph_built()) {
    // A region of half the mesh or more builds the whole graph once and keeps it, as the
    // whole mesh's constraints do: no more memory than twice its own part, and no graph
    // rebuilt at every set_constraints.
    const std::vector<int> faces = faces_around(neighbours(), roles.free_vertices);
    if (2 * static_cast<Eigen::Index>(faces.size()) < faces_.rows()) {
      const RegionGraph region = region_graph(rest_, neighbours(), faces, domain_, clamp_negative_weights_);
      return layout_on(region.part(), std::move(roles), sets);
    }
  }
  return layout_on(GraphPart{&whole().graph, &rest_}, std::move(roles), sets);
}

}  // namespace edgedeform
