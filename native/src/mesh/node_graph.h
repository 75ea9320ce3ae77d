// The deformation graph of either domain: nodes, arcs and cotangent arc weights.
//
// Primal: a node per vertex, an arc per mesh edge, w_ab = 1/2 sum of the opposite cotangents.
// Edge: a node per mesh edge (its midpoint); in each triangle (a,b,c) the nodes of edges
// (c,a) and (a,b) are joined with w = 1/2 cot(angle at a) -- the cotangent weight of the
// midpoint triangle, i.e. 1/4 of the Crouzeix-Raviart stiffness matrix (docs/design.md §3).
#pragma once

#include <vector>

#include "mesh/edge_topology.h"
#include "base/types.h"

namespace edgedeform {

struct NodeGraph {
  Domain domain = Domain::Edge;
  int n_vertices = 0;
  int n_nodes = 0;
  // Vertices that define each node: p_i = (x_a + x_b) / 2 with (a,b) = node_vertices.row(i);
  // in the primal domain a == b == i.
  RowMatrixX2i node_vertices;
  // Undirected arcs i < j with their weights (after clamping, when asked).
  RowMatrixX2i arcs;
  Eigen::VectorXd arc_weights;
  // Symmetric adjacency in CSR form: neighbours of node i are
  // adjacency[offsets[i] .. offsets[i+1]) with weights adjacency_weights[...].
  std::vector<int> offsets;
  std::vector<int> adjacency;
  std::vector<double> adjacency_weights;

  // Node positions p = P x.
  RowMatrixX3d node_positions(const RowMatrixX3d& X) const;
  // Row i of P x alone.
  Eigen::RowVector3d node_position(const RowMatrixX3d& X, int i) const {
    return 0.5 * (X.row(node_vertices(i, 0)) + X.row(node_vertices(i, 1)));
  }
  // P (n_nodes x n_vertices): D in the edge domain, I in the primal one.
  SparseMatrix node_matrix() const;
  // Graph Laplacian: L_ii = sum_j w_ij, L_ij = -w_ij.
  SparseMatrix laplacian() const;
};

NodeGraph build_node_graph(const RowMatrixX3d& V, const RowMatrixX3i& F,
                           const EdgeTopology& topology, Domain domain,
                           bool clamp_negative_weights);

}  // namespace edgedeform
