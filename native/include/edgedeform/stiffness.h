// Per-vertex stiffness lambda in [0,1] mapped to the nodes (paper §3.2.4).
#pragma once

#include "edgedeform/node_graph.h"

namespace edgedeform {

// Throws std::invalid_argument when a value is outside [0,1] or not finite.
void check_stiffness(const Eigen::VectorXd& vertex_lambda, int n_vertices);

// Primal: the vertex's own value. Edge: the mean of the edge's two endpoints.
Eigen::VectorXd node_stiffness(const NodeGraph& graph, const Eigen::VectorXd& vertex_lambda);

}  // namespace edgedeform
