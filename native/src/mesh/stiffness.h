// Per-vertex stiffness lambda in [0,1] mapped to the nodes (paper §3.2.4).
#pragma once

#include "mesh/node_graph.h"

namespace edgedeform {

// Throws std::invalid_argument when a value is outside [0,1] or not finite.
void check_stiffness(const Eigen::VectorXd& vertex_lambda, int n_vertices);

// Primal: the vertex's own value. Edge: the mean of the edge's two endpoints.
Eigen::VectorXd node_stiffness(const NodeGraph& graph, const Eigen::VectorXd& vertex_lambda);

// The primal similarity floor (docs/deviations.md, "primal similarity floor"). The primal
// Laplacian term has one 3-vector row per node, about as many as free unknowns, so on its
// own it pins neither the rotations nor the scales its targets s_i R_i delta_i are made of:
// at lambda = 0 the iteration drifts (dino lift: the shape grew to 1.9x its width and never
// settled) or oscillates (head). So a primal term with lambda below the floor keeps a
// floor - lambda share of an as-similar-as-possible 1-form term, sum_j w_ij |e_ij - s_i R_i
// e0_ij|^2, taken from its Laplacian share: it pins R_i and s_i to the edges around the node
// yet, like the Laplacian term, leaves uniform scale and rigid motion free (docs/design.md §3's fixed
// points of lambda = 0 stay fixed points). The edge domain has three times as many rows and
// converges without it.
constexpr double kPrimalSimilarityFloor = 0.01;

// The similarity floor of a domain's terms: kPrimalSimilarityFloor in the primal domain, 0
// in the edge domain.
inline double similarity_floor(Domain domain) { return domain == Domain::Primal ? kPrimalSimilarityFloor : 0.0; }

// Per term: the share of the similarity 1-form term, max(floor - lambda, 0).
Eigen::VectorXd similarity_share(const Eigen::VectorXd& term_lambda, double floor);

}  // namespace edgedeform
