// The local step: per node, the rotation and isotropic scale that best fit its 1-form.
#pragma once

#include <vector>

#include "local_fit/rotation_fit.h"
#include "base/types.h"

namespace edgedeform {

// The energy terms the solver evaluates. Term t belongs to one node; its arcs point to
// neighbour nodes. Node indices refer to a node-position array chosen by the caller.
struct NodeStencil {
  int n_terms = 0;
  std::vector<int> self;          // #terms: index of the term's own node
  std::vector<int> offsets;       // #terms+1: arcs of term t are offsets[t] .. offsets[t+1)
  std::vector<int> neighbour;     // #arcs: index of the neighbour node
  std::vector<double> weight;     // #arcs: w_ij (0 for a clamped arc: kept for its direction)
  RowMatrixX3d rest_edge;         // #arcs: e0_ij = p0_i - p0_j
  RowMatrixX3d rest_laplacian;    // #terms: delta0_i = sum_j w_ij e0_ij
  Eigen::VectorXd rest_norm;      // #terms: sum_j w_ij |e0_ij|^2

  int n_arcs() const { return static_cast<int>(neighbour.size()); }
};

// The terms of `term_nodes` (global node ids) of `graph`, with the rest vertex positions
// `rest_vertices` (only the nodes the terms touch are placed: a small region of a large
// mesh costs what the region does); `position_index` maps a global node id to its row in the position arrays the
// stencil will be evaluated on. Arcs of weight 0 stay: they add nothing to the energy, but
// their directions settle the rotation of a node whose weighted arcs are all collinear.
struct NodeGraph;
NodeStencil build_stencil(const NodeGraph& graph, const RowMatrixX3d& rest_vertices,
                          const std::vector<int>& term_nodes, const std::vector<int>& position_index);

// Result of the local step for every term.
struct LocalFit {
  std::vector<Eigen::Matrix3d> rotation;  // R_i
  // Right singular vectors of each S_i: the start of the next fit (reset to I when the
  // size does not match the stencil).
  std::vector<Eigen::Matrix3d> right_vectors;
  Eigen::VectorXd scale;                  // s_i
  Eigen::VectorXd term_energy;            // each term's share of E
  double energy = 0.0;                    // E(x) with these R_i, s_i (docs/design.md §3)
};

// Scale bounds. A neighbourhood scaled by more than 4x (or less than 1/4) is no longer a
// plausible local similarity; with lambda near 0 an unbounded s feeds back into the next
// global step and a few sharp features (horns, teeth) run away: measured on the open head
// in the primal domain, s up to the old bound 100 exploded the mesh (mean edge strain 14),
// with these bounds the same iteration stays bounded (0.5).
constexpr double kMinScale = 0.25;
constexpr double kMaxScale = 4.0;

// Fits R_i, s_i to `node_positions` for every term (in parallel) and evaluates the energy
// with term stiffness `term_lambda` (#terms) and similarity shares `term_similar` (#terms,
// or empty for none; stiffness.h). When `fit` already holds one rotation per term (the
// previous iteration's), each fit starts from it.
void fit_local(const NodeStencil& stencil, const RowMatrixX3d& node_positions,
               const Eigen::VectorXd& term_lambda, LocalFit& fit,
               const Eigen::VectorXd& term_similar = {});

}  // namespace edgedeform
