// The public solver: a mesh, its graph, constraints and stiffness, and the local/global
// iteration of docs/design.md §4. Each setter validates before it changes anything, so a failed call
// leaves the Deformer as it was.
//
// It wires the core's parts together, as libigl's arap_precomputation / arap_solve pair:
// the precomputation (ensure_factored, on the first solve after a change) takes the
// operators from operator_cache.h and their factor from factor_cache.h; solve() starts from
// warm_state.h and runs a strategy, plain/Anderson (fixed_point_iteration.h) or projected
// Newton (projected_newton.h, after an Anderson lead-in), on one FixedPointProblem.
#pragma once

#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "edgedeform/constrained_system.h"
#include "edgedeform/edge_topology.h"
#include "edgedeform/factor_cache.h"
#include "edgedeform/fixed_point_iteration.h"
#include "edgedeform/newton_factor.h"
#include "edgedeform/projected_newton.h"
#include "edgedeform/node_graph.h"
#include "edgedeform/operator_cache.h"
#include "edgedeform/seams.h"
#include "edgedeform/sparse_cholesky.h"
#include "edgedeform/stiffness.h"
#include "edgedeform/warm_state.h"

namespace edgedeform {

enum class Acceleration { None, Anderson, Newton };
const char* acceleration_name(Acceleration a);
// "none" | "anderson" | "newton"; anything else throws std::invalid_argument.
Acceleration parse_acceleration(const std::string& name);

// The Newton method's settings (acceleration Newton).
struct NewtonOptions {
  // A cold or moved-target start first runs up to this many Anderson iterations: they settle
  // the stiff part of the error cheaply and keep the solve in the basin Anderson finds (the
  // head lift without them: another minimum, 3.6e-3 of the diagonal away; docs/decisions/0029).
  int lead_in = 100;
  // For the diagnostic that chose the method (bench/bench_newton.py, docs/decisions/0029):
  // lambda = 1: "ladder" (default) projects only the terms below a level that factors;
  // "full" uses K itself where it factors and else projects every indefinite term.
  // `lifted` (default) moves each trial along the step's rotation response, else straight.
  bool ladder = true;
  bool lifted = true;
};

struct SolveOptions {
  int max_iterations = 2000;
  // Converged: the estimated largest vertex distance to the fixed point is below
  // tolerance * (rest bounding-box diagonal). See convergence.h.
  double tolerance = 1e-3;
  bool warm_start = true;
  std::optional<RowMatrixX3d> initial;  // start with a local step on these positions
  Acceleration acceleration = Acceleration::Anderson;
  int anderson_window = 5;
  // Plain/Anderson: before a convergence claim, estimate J_G's largest modulus by Arnoldi
  // steps at the point (claim_check.h) and claim only if the bound with it holds too.
  bool verify_claims = false;
  NewtonOptions newton;
  // Asked once per iteration (called from the solving thread); returning true stops the
  // solve with SolveInterrupted. The Python bindings check for Ctrl-C here, so the core
  // needs no Python.
  std::function<bool()> interrupt_requested;
};

struct SolveResult {
  RowMatrixX3d positions;
  int iterations = 0;
  std::vector<double> energies;                 // after each iteration
  // Per iteration: |G(y) - y|_inf / diag for the point y its global step started from
  // (for the plain method |x_k - x_{k-1}|, the largest vertex move, over the rest diagonal).
  std::vector<double> residuals;
  double distance_estimate = 0.0;               // of the result to the fixed point, / diag
  int accelerated_steps = 0, rejected_steps = 0;  // Anderson steps taken; discarded by the safeguard
  int newton_steps = 0;                         // Newton: steps taken
  int line_search_failures = 0;                 // Newton steps that gave way to plain steps
  int newton_factorizations = 0;                // Newton: factorizations of K (failed ones included)
  int newton_fallbacks = 0;                     // Newton's steps stopped lowering the merit: Anderson finished
  double assemble_ms = 0.0, newton_factor_ms = 0.0;  // Newton: assembling K, factoring it (totals)
  int claim_checks = 0, refused_claims = 0;     // verify_claims: checks made, claims refused
  std::optional<double> initial_energy;         // energy of `initial`, when given
  bool converged = false;
  std::vector<std::string> warnings;
  double factor_ms = 0.0;                       // assembly + factorization in this call
  double local_ms = 0.0, rhs_ms = 0.0, solve_ms = 0.0;  // totals over the iterations
  int free_vertices = 0;
  int active_nodes = 0;
};

// Positions farther than `limit` (per coordinate) from `center` would overflow the energies.
struct SafeRange {
  Eigen::RowVector3d center = Eigen::RowVector3d::Zero();
  double limit = 0.0;
};

class Deformer {
 public:
  Deformer(const RowMatrixX3d& V, const RowMatrixX3i& F, Domain domain,
           bool clamp_negative_weights = true);

  void set_constraints(const ConstraintSets& sets);
  void set_stiffness(double lambda);
  void set_stiffness(const Eigen::VectorXd& vertex_lambda);
  // targets: (#handles x 3) in the order of the handles.
  SolveResult solve(const RowMatrixX3d& targets, const SolveOptions& options);
  // Energy of positions X over every node, with R_i, s_i fitted to X.
  double energy(const RowMatrixX3d& X) const;

  // Inspection of the one-step map and its derivative (tests, diagnostics). X (#V x 3) is a full shape
  // whose constrained rows give the fixed vertices; vectors are over the free vertices
  // (#free x 3, in free_vertices() order). Each factors the system first if needed.
  Eigen::MatrixXd one_step_map(const RowMatrixX3d& X);  // G(X)
  // J_G dX, or K dX = A (I - J_G) dX with `newton_operator`.
  Eigen::MatrixXd jacobian_product(const RowMatrixX3d& X, const Eigen::MatrixXd& dX, bool newton_operator);
  // The two halves of G, for diagnostics in other coordinates (bench_spectrum.py --radius,
  // bench/rotation_coordinates.py): the local fit at X (R_i, s_i per energy term), and the
  // global step's free positions for given R_i, s_i, the fixed rows taken from X.
  // global_step_with(X, local_fit_at(X)) is G(X).
  LocalFit local_fit_at(const RowMatrixX3d& X);
  Eigen::MatrixXd global_step_with(const RowMatrixX3d& X, const std::vector<Eigen::Matrix3d>& rotation,
                                   const Eigen::VectorXd& scale);
  // The Newton matrix K at X (3 #free x 3 #free, row 3 v + c coordinate c of free vertex v):
  // `projection` as linearize_fit's (0: K itself).
  SparseMatrix newton_matrix_at(const RowMatrixX3d& X, double projection = 0.0);
  const std::vector<int>& free_vertices() const;

  int n_vertices() const { return static_cast<int>(rest_.rows()); }
  int n_faces() const { return static_cast<int>(faces_.rows()); }
  Domain domain() const { return graph_.domain; }
  const RowMatrixX3d& rest() const { return rest_; }
  const RowMatrixX3i& faces() const { return faces_; }
  const EdgeTopology& topology() const { return topology_; }
  const NodeGraph& graph() const { return graph_; }
  const Eigen::VectorXd& node_lambda() const { return node_lambda_; }
  const Eigen::VectorXd& vertex_lambda() const { return vertex_lambda_; }
  int analyses() const { return factors_.analyses(); }
  int orderings() const { return factors_.orderings(); }
  int factorizations() const { return factors_.factorizations(); }
  // How many constraint sets were assembled whole (sparse products); a set restricted from
  // the base set's operators does not count (tests check reuse).
  int assemblies() const { return operators_.assemblies(); }
  double factor_nonzeros() const { return factors_.factor_nonzeros(); }

 private:
  // The FixedPointProblem of the current system: the local step, the global step with
  // assembled_ and the factor; both strategies iterate on it.
  struct StepProblem;
  // Operators and factor of the current constraints and stiffness (the precomputation).
  void ensure_factored(SolveResult& result);
  // For the inspection calls: factors if needed, fits the local step at X's free rows and
  // returns the fixed vertices' share c; x_local and fit hold the point.
  Eigen::MatrixXd prepare_point(const RowMatrixX3d& X, RowMatrixX3d& x_local, LocalFit& fit);
  // Where a solve starts: iter_ continued (same targets, warm) or restarted (from the last
  // iterate when warm, else from rest; `initial` when given); returns the fit to start with.
  LocalFit start_point(const RowMatrixX3d& targets, const SolveOptions& options, RowMatrixX3d& x_local,
                       SolveResult& result);
  // The fixed point by Newton steps (projected_newton.h), after the Anderson lead-in.
  void iterate_newton(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit, SolveResult& result);
  // The fixed point by plain or Anderson steps (fixed_point_iteration.h) for `budget` iterations.
  void iterate_plain_anderson(FixedPointProblem& problem, const SolveOptions& options, int budget, LocalFit& fit,
                              SolveResult& result);
  // One local step on free positions y (fixed rows of x_local already set).
  void local_step(const Eigen::MatrixXd& y, RowMatrixX3d& x_local, LocalFit& fit, SolveResult& result);

  RowMatrixX3d rest_;
  RowMatrixX3i faces_;
  EdgeTopology topology_;
  NodeGraph graph_;
  std::vector<bool> referenced_;
  SafeRange safe_range_;  // targets and initial positions are checked against it
  SeamCopies seams_;      // coincident vertices: a solve that tears them apart warns
  double seam_tolerance_ = 0.0;  // 1e-6 of the bounding-box diagonal: a visible gap
  Eigen::VectorXd vertex_lambda_;
  Eigen::VectorXd node_lambda_;
  std::shared_ptr<const ConstrainedSystem> system_;
  std::shared_ptr<const AssembledSystem> assembled_;  // null when the constraints changed
  bool stiffness_changed_ = false;              // assembled_ holds another lambda
  OperatorCache operators_;  // assembles or restricts system_'s operators
  FactorCache factors_;      // factors assembled_'s A; its factor() is the current one
  NewtonFactor newton_factor_;  // the Newton matrix of assembled_ and its factor
  WarmState warm_;           // the fit the next warm solve starts from
  // The iteration in progress, continued by a warm solve with the same targets (live editing
  // that stands still settles to the cold solve's fixed point). Owned by solve(); stale after
  // any change of system (ensure_factored) or of targets.
  struct Iteration {
    bool continuable = false;     // same system and fit(y) == the warm state's fit
    bool positions_valid = false;  // y holds the free vertices of the current constraints
    RowMatrixX3d targets;
    Eigen::MatrixXd y;            // current iterate (free vertices)
    double energy = 0.0;          // E(y)
    PlainAndersonMemory plain;    // the plain/Anderson strategy's state (fixed_point_iteration.h)
    NewtonMemory newton;          // Newton's state (projected_newton.h)
    bool newton_valid = false;    // newton describes this iteration (false after Anderson)
    int lead_in_iterations = 0;   // Newton's Anderson lead-in done since the targets were set
  } iter_;
  double diag_ = 0.0;             // rest bounding-box diagonal
  std::vector<double> rhs_term_weights_;  // RotationOperator::apply scratch
  RowMatrixX3d node_positions_;    // local-step scratch
  mutable std::unique_ptr<NodeStencil> full_stencil_;  // for energy(), built on first use
  // The bindings release the GIL: two Python threads sharing a Deformer take turns here.
  mutable std::mutex mutex_;
};

}  // namespace edgedeform
