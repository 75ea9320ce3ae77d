#include "mesh/stiffness.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace edgedeform {

void check_stiffness(const Eigen::VectorXd& lambda, int n_vertices) {
  if (lambda.size() != n_vertices)
    throw std::invalid_argument("stiffness has " + std::to_string(lambda.size()) + " values, expected one per vertex (" +
                                std::to_string(n_vertices) + ")");
  for (Eigen::Index v = 0; v < lambda.size(); ++v)
    if (!(lambda(v) >= 0.0 && lambda(v) <= 1.0))  // also rejects NaN
      throw std::invalid_argument("stiffness[" + std::to_string(v) + "] = " + std::to_string(lambda(v)) +
                                  " is outside [0, 1]");
}

Eigen::VectorXd node_stiffness(const NodeGraph& graph, const Eigen::VectorXd& lambda) {
  Eigen::VectorXd node(graph.n_nodes);
  for (int i = 0; i < graph.n_nodes; ++i)
    node(i) = 0.5 * (lambda(graph.node_vertices(i, 0)) + lambda(graph.node_vertices(i, 1)));
  return node;
}

Eigen::VectorXd similarity_share(const Eigen::VectorXd& lambda, double floor) {
  return (floor - lambda.array()).max(0.0).matrix();
}

}  // namespace edgedeform
