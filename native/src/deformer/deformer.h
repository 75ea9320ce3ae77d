// The public solver: a mesh, its graph, constraints and stiffness, and the local/global
// iteration of docs/design.md §4. Each setter validates before it changes anything, so a failed call
// leaves the Deformer as it was.
//
// It wires the core's parts together, as libigl's arap_precomputation / arap_solve pair:
// the precomputation (ensure_factored, on the first solve after a change) takes the
// operators from operator_cache.h and their factor from factor_cache.h; solve() starts from
// warm_state.h and runs a strategy, plain/Anderson (fixed_point_iteration.h) or L-BFGS
// (quasi_newton.h), on one FixedPointProblem.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "system/constrained_system.h"
#include "mesh/edge_topology.h"
#include "mesh/mesh_incidence.h"
#include "system/factor_cache.h"
#include "strategies/iteration_state.h"
#include "mesh/node_graph.h"
#include "system/operator_cache.h"
#include "mesh/seams.h"
#include "base/solve_types.h"
#include "linear_algebra/sparse_cholesky.h"
#include "mesh/stiffness.h"
#include "system/warm_state.h"

namespace edgedeform {

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
  // J_G dX, or K dX = A (I - J_G) dX with `k_product` (bench/soft_modes.py: J_G's soft modes).
  Eigen::MatrixXd jacobian_product(const RowMatrixX3d& X, const Eigen::MatrixXd& dX, bool k_product);
  // The two halves of G, for the diagnostics in other coordinates (bench/arc_anderson.py):
  // the local fit at X (R_i, s_i per energy term), and the global step's free positions for
  // given R_i, s_i, the fixed rows taken from X. global_step_with(X, local_fit_at(X)) is G(X).
  LocalFit local_fit_at(const RowMatrixX3d& X);
  Eigen::MatrixXd global_step_with(const RowMatrixX3d& X, const std::vector<Eigen::Matrix3d>& rotation,
                                   const Eigen::VectorXd& scale);
  const std::vector<int>& free_vertices() const;

  int n_vertices() const { return static_cast<int>(rest_.rows()); }
  int n_faces() const { return static_cast<int>(faces_.rows()); }
  int n_nodes() const { return domain_ == Domain::Edge ? incidence_.n_edges() : n_vertices(); }
  Domain domain() const { return domain_; }
  const RowMatrixX3d& rest() const { return rest_; }
  const RowMatrixX3i& faces() const { return faces_; }
  // Who neighbours whom, through the faces around each vertex (valid while the Deformer lives).
  VertexNeighbours neighbours() const { return {faces_, incidence_}; }
  // The whole mesh's topology and node graph, built on first use: a solve over a region
  // builds only the region's part (region_graph.h), so these cost memory only when asked for
  // (inspection, energy()) or when a set of constraints reaches half the mesh or more.
  const EdgeTopology& topology() const { return whole().topology; }
  const NodeGraph& graph() const { return whole().graph; }
  // Lambda per node under the current stiffness (#nodes).
  Eigen::VectorXd node_lambda() const;
  // Whether the whole graph was built (tests: a region's solve must not need it).
  bool whole_graph_built() const;
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
  // The strategy a solve runs: `asked`, with Automatic resolved by the measured rule (L-BFGS
  // where lambda = 1 on every term, else Anderson) and L-BFGS, which descends E, replaced by
  // Anderson where there is no E (some lambda < 1).
  Acceleration strategy_for(Acceleration asked) const;
  // The fixed point by plain or Anderson steps (fixed_point_iteration.h).
  void iterate_plain_anderson(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                              SolveResult& result);
  // The fixed point by L-BFGS on E (quasi_newton.h).
  void iterate_quasi_newton(FixedPointProblem& problem, const SolveOptions& options, LocalFit& fit,
                            SolveResult& result);
  // One local step on free positions y (fixed rows of x_local already set).
  void local_step(const Eigen::MatrixXd& y, RowMatrixX3d& x_local, LocalFit& fit, SolveResult& result);

  struct WholeGraph {
    EdgeTopology topology;
    NodeGraph graph;
  };
  const WholeGraph& whole() const;
  // The graph part the layout of `roles` needs: the whole graph when built or when the region
  // reaches half the faces or more, else the region's own.
  ConstrainedSystem layout(VertexRoles roles, const ConstraintSets& sets) const;

  RowMatrixX3d rest_;
  RowMatrixX3i faces_;
  Domain domain_;
  bool clamp_negative_weights_;
  MeshIncidence incidence_;  // faces per vertex, edge numbers: what regions and walks are built from
  std::vector<bool> referenced_;
  SafeRange safe_range_;  // targets and initial positions are checked against it
  SeamCopies seams_;      // coincident vertices: a solve that tears them apart warns
  double seam_tolerance_ = 0.0;  // 1e-6 of the bounding-box diagonal: a visible gap
  Eigen::VectorXd vertex_lambda_;
  std::shared_ptr<const ConstrainedSystem> system_;
  std::shared_ptr<const AssembledSystem> assembled_;  // null when the constraints changed
  bool stiffness_changed_ = false;              // assembled_ holds another lambda
  OperatorCache operators_;  // assembles or restricts system_'s operators
  FactorCache factors_;      // factors assembled_'s A; its factor() is the current one
  WarmState warm_;           // the fit the next warm solve starts from
  IterationState iter_;      // the iteration a warm solve with the same targets continues
  bool all_rigid_ = false;   // lambda = 1 on every term of assembled_: the iteration descends E
  double diag_ = 0.0;             // rest bounding-box diagonal
  std::vector<double> rhs_term_weights_;  // RotationOperator::apply scratch
  RowMatrixX3d node_positions_;    // local-step scratch
  mutable std::unique_ptr<NodeStencil> full_stencil_;  // for energy(), built on first use
  mutable std::unique_ptr<const WholeGraph> whole_;     // built on first use, then never changed
  mutable std::mutex whole_mutex_;                      // guards building whole_; taken after mutex_
  // The bindings release the GIL: two Python threads sharing a Deformer take turns here.
  mutable std::mutex mutex_;
};

}  // namespace edgedeform
