// The deformation problem once constraints are known: which vertices are free, which node
// terms touch them (region of interest), and the sparse operators of the global step.
//
// With free vertices x_f and fixed ones x_c, the energy of docs/design.md §3 over the active terms is
//   E = sum_a W1_a |J1_a x - R_i(a) e0_a|^2 + sum_t W2_t |J2_t x - s_t R_t delta0_t|^2,
// with J1 the arc differences (P_i - P_j) and J2 the graph Laplacian rows times P,
// W1_a = lambda_i w_a, W2_t = 1 - lambda_t. Its normal equations, restricted to x_f, are
//   A x_f = H Z + c,   A = J1f^T W1 J1f + J2f^T W2 J2f,
// where Z stacks the entries of every R_t and s_t R_t. H is kept as a RotationOperator, so
// that the right side of one iteration is a single sparse product.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "local_fit/local_step.h"
#include "mesh/node_graph.h"
#include "mesh/region_graph.h"
#include "system/rotation_operator.h"
#include "mesh/mesh_incidence.h"

namespace edgedeform {

struct ConstraintSets {
  std::vector<int> handles;
  std::vector<int> statics;
  std::optional<std::vector<int>> roi;  // nullopt: the whole mesh
  // Instead of roi: the vertices within this distance of a handle in the rest positions
  // (region_by_distance.h), along the mesh edges when roi_connected.
  std::optional<double> roi_radius;
  bool roi_connected = false;
  // The vertices roi_radius is measured from (nullopt: the handles). Grab measures from the
  // vertices it drags, as Blender's proportional editing from the selection, while the
  // other handles it pins are handles too.
  std::optional<std::vector<int>> roi_from;
};

struct ConstrainedSystem {
  int n_vertices = 0;
  std::vector<int> handles;          // as given; targets come in this order
  std::vector<int> free_vertices;    // global ids; local id = position
  std::vector<int> fixed_vertices;   // fixed vertices the terms touch; local id = nf + position
  std::vector<int> term_nodes;       // active nodes (global ids); stencil node t < #terms
  std::vector<int> stencil_nodes;    // active nodes, then their other neighbours (global ids)
  RowMatrixX2i stencil_node_vertices;  // per stencil node: its (a,b) in local vertex ids
  NodeStencil stencil;               // indices into the stencil-node position array
  double rest_scale = 0.0;           // sum of stencil.rest_norm: the energy's natural size
  double similarity_floor = 0.0;     // of the graph's domain (stiffness.h)
  // Only in a system built whole (build_constrained_system, add_jacobians); one whose
  // operators are restricted from another's (system_restriction.h) goes without.
  SparseMatrix J1f, J1c;             // #arcs x nf, #arcs x nc
  SparseMatrix J2f, J2c;             // #terms x nf, #terms x nc
  bool has_jacobians = false;
  std::vector<std::string> warnings;

  int n_free() const { return static_cast<int>(free_vertices.size()); }
  int n_fixed() const { return static_cast<int>(fixed_vertices.size()); }
  int n_terms() const { return stencil.n_terms; }
};

// What constraint sets make of each vertex.
enum VertexRole : char { kFree = 0, kHandle = 1, kAtRest = 2 };

struct VertexRoles {
  std::vector<VertexRole> role;    // #V
  std::vector<int> free_vertices;  // ascending
  std::vector<std::string> warnings;
};

// The roles under `sets`: validated first (std::invalid_argument / std::out_of_range for bad
// sets), the region picked, free components that touch no constraint left at rest.
VertexRoles vertex_roles(const RowMatrixX3d& rest, const VertexNeighbours& neighbours, const std::vector<bool>& referenced,
                         const ConstraintSets& sets);

// Everything but J1, J2: local ids, active terms, stencil, on a graph part that holds every
// arc of the terms the free vertices need (the whole graph, or region_graph of faces_around
// the free vertices).
ConstrainedSystem layout_on(const GraphPart& part, VertexRoles roles, const ConstraintSets& sets);

// Throws std::invalid_argument / std::out_of_range for bad constraint sets.
// = constrained_layout, then add_jacobians.
ConstrainedSystem build_constrained_system(const NodeGraph& graph, const RowMatrixX3d& rest,
                                           const VertexNeighbours& neighbours,
                                           const std::vector<bool>& referenced,
                                           const ConstraintSets& sets);

// vertex_roles, then layout_on the whole graph. Throws like build_constrained_system.
ConstrainedSystem constrained_layout(const NodeGraph& graph, const RowMatrixX3d& rest,
                                     const VertexNeighbours& neighbours, const std::vector<bool>& referenced,
                                     const ConstraintSets& sets);

// Positions of the stencil nodes (#stencil nodes x 3) from local vertex positions
// (free, then fixed): each node is the mean of its two vertex slots.
void stencil_node_positions(const ConstrainedSystem& system, const RowMatrixX3d& x_local, RowMatrixX3d& p);

// J1f, J1c, J2f, J2c of a layout.
void add_jacobians(ConstrainedSystem& system);

// Elimination order of the free vertices (their local ids, 0 .. nf-1) by `rank` (#V, one
// rank per global vertex, -1 for none); empty when some free vertex has no rank. A subset
// of a fill-reducing order eliminated in the same order never fills more than the whole
// did, so a constraint set that frees only vertices an earlier set freed (a handle group
// added, then removed again) is factored without computing a new ordering.
std::vector<int> free_vertex_order(const ConstrainedSystem& system, const std::vector<int>& rank);

// The lambda-dependent operators.
struct AssembledSystem {
  SparseMatrix A;                 // nf x nf, symmetric
  RotationOperator H;             // the H Z product, nf x (#terms rotations and scales); lambda-free
                                  // coefficients, weighed by term_lambda
  SparseMatrix K_fixed;           // J1f^T W1 J1c + J2f^T W2 J2c: A's coupling to x_c (nf x nc)
  Eigen::VectorXd term_lambda;    // #terms
  Eigen::VectorXd term_similar;   // #terms: phi_t, the similarity 1-form share (stiffness.h)
  bool laplacian_term = false;    // some term has lambda < 1
};

AssembledSystem assemble_system(const ConstrainedSystem& system, const Eigen::VectorXd& vertex_lambda);

// The right-hand-side operator of `system` (lambda-free; every term's lambda is 1).
// assemble_system, rotation_operator and update_stiffness need the system's J1, J2 (else
// std::logic_error).
RotationOperator rotation_operator(const ConstrainedSystem& system);

// The same system at other stiffness: A, K_fixed and the operator's per-term lambda are
// replaced; H's coefficients and the pattern of A (for lambda < 1 somewhere) stay.
void update_stiffness(AssembledSystem& assembled, const ConstrainedSystem& system,
                      const Eigen::VectorXd& vertex_lambda);

// Lambda of each term: its node's, the mean of the node's two vertices' (node_stiffness for the
// terms alone). vertex_lambda has one value per mesh vertex (else std::logic_error), as in
// every call below that takes it.
Eigen::VectorXd term_stiffness(const ConstrainedSystem& system, const Eigen::VectorXd& vertex_lambda);

// term_lambda, laplacian_term and the operator's per-term lambda from vertex_lambda.
void set_term_stiffness(AssembledSystem& assembled, const ConstrainedSystem& system,
                        const Eigen::VectorXd& vertex_lambda);

// Whether `assembled` (of `system`) holds vertex_lambda's stiffness on every term.
bool assembled_at(const AssembledSystem& assembled, const ConstrainedSystem& system,
                  const Eigen::VectorXd& vertex_lambda);


}  // namespace edgedeform
