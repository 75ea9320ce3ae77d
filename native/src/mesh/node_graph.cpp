#include "mesh/node_graph.h"

#include <algorithm>
#include <vector>

#include "base/bucket_order.h"
#include "mesh/cotangent.h"

namespace edgedeform {

namespace {

// Node pair joined by corner k of face f, in the given domain (see the header).
std::pair<int, int> corner_arc(const RowMatrixX3i& F, const EdgeTopology& topo, Domain domain,
                               Eigen::Index f, int k) {
  const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
  if (domain == Domain::Primal) return {F(f, k1), F(f, k2)};
  return {topo.face_edges(f, k1), topo.face_edges(f, k2)};
}

}  // namespace

NodeGraph build_node_graph(const RowMatrixX3d& V, const RowMatrixX3i& F, const EdgeTopology& topo,
                           Domain domain, bool clamp_negative_weights) {
  NodeGraph g;
  g.domain = domain;
  g.n_vertices = static_cast<int>(V.rows());
  if (domain == Domain::Edge) {
    g.node_vertices = topo.edges;
  } else {
    g.node_vertices.resize(V.rows(), 2);
    for (Eigen::Index v = 0; v < V.rows(); ++v) g.node_vertices.row(v).setConstant(static_cast<int>(v));
  }
  g.n_nodes = static_cast<int>(g.node_vertices.rows());

  // Every corner adds 1/2 cot(angle) to one arc (i, j), i < j; arcs met in several
  // triangles add up, in face order. The corners are grouped by i (a counting sort), then
  // each group by (j, corner): the arcs come out in lexicographic order.
  const auto n_corners = static_cast<size_t>(3 * F.rows());
  std::vector<int> first(n_corners), second(n_corners);
  std::vector<double> half_cot(n_corners);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d a = V.row(F(f, k)).transpose();
      const Eigen::Vector3d u = V.row(F(f, (k + 1) % 3)).transpose() - a;
      const Eigen::Vector3d v = V.row(F(f, (k + 2) % 3)).transpose() - a;
      auto [i, j] = corner_arc(F, topo, domain, f, k);
      if (i > j) std::swap(i, j);
      const auto c = static_cast<size_t>(3 * f + k);
      first[c] = i;
      second[c] = j;
      half_cot[c] = 0.5 * safe_cotangent(u, v);
    }
  }
  Buckets by_first = bucket_order(first, g.n_nodes);
  std::vector<int>& order = by_first.order;
  for (int i = 0; i < g.n_nodes; ++i)
    std::sort(order.begin() + by_first.offsets[static_cast<size_t>(i)],
              order.begin() + by_first.offsets[static_cast<size_t>(i) + 1], [&](int x, int y) {
                return second[static_cast<size_t>(x)] != second[static_cast<size_t>(y)]
                           ? second[static_cast<size_t>(x)] < second[static_cast<size_t>(y)]
                           : x < y;
              });
  std::vector<int>().swap(by_first.offsets);

  std::vector<int> ai, aj;
  std::vector<double> aw;
  ai.reserve(n_corners);
  aj.reserve(n_corners);
  aw.reserve(n_corners);
  for (size_t s = 0; s < order.size();) {
    const auto c0 = static_cast<size_t>(order[s]);
    double w = 0.0;
    size_t e = s;
    for (; e < order.size() && first[static_cast<size_t>(order[e])] == first[c0] &&
           second[static_cast<size_t>(order[e])] == second[c0];
         ++e)
      w += half_cot[static_cast<size_t>(order[e])];
    ai.push_back(first[c0]);
    aj.push_back(second[c0]);
    aw.push_back(clamp_negative_weights ? std::max(w, 0.0) : w);
    s = e;
  }
  // Freed before the adjacency is built: 3.4M corners' ids and weights at 560k vertices.
  for (std::vector<int>* v : {&first, &second, &order}) std::vector<int>().swap(*v);
  std::vector<double>().swap(half_cot);
  const Eigen::Index n_arcs = static_cast<Eigen::Index>(ai.size());
  g.arcs.resize(n_arcs, 2);
  g.arc_weights.resize(n_arcs);
  std::vector<int> degree(static_cast<size_t>(g.n_nodes), 0);
  for (Eigen::Index a = 0; a < n_arcs; ++a) {
    g.arcs(a, 0) = ai[static_cast<size_t>(a)];
    g.arcs(a, 1) = aj[static_cast<size_t>(a)];
    g.arc_weights(a) = aw[static_cast<size_t>(a)];
    ++degree[static_cast<size_t>(ai[static_cast<size_t>(a)])];
    ++degree[static_cast<size_t>(aj[static_cast<size_t>(a)])];
  }
  g.offsets.assign(static_cast<size_t>(g.n_nodes) + 1, 0);
  for (int i = 0; i < g.n_nodes; ++i) g.offsets[static_cast<size_t>(i) + 1] = g.offsets[static_cast<size_t>(i)] + degree[static_cast<size_t>(i)];
  g.adjacency.resize(static_cast<size_t>(g.offsets.back()));
  g.adjacency_weights.resize(g.adjacency.size());
  std::vector<int> cursor(g.offsets.begin(), g.offsets.end() - 1);
  for (Eigen::Index a = 0; a < n_arcs; ++a) {
    const int i = g.arcs(a, 0), j = g.arcs(a, 1);
    const double w = g.arc_weights(a);
    g.adjacency[static_cast<size_t>(cursor[static_cast<size_t>(i)])] = j;
    g.adjacency_weights[static_cast<size_t>(cursor[static_cast<size_t>(i)]++)] = w;
    g.adjacency[static_cast<size_t>(cursor[static_cast<size_t>(j)])] = i;
    g.adjacency_weights[static_cast<size_t>(cursor[static_cast<size_t>(j)]++)] = w;
  }
  return g;
}

RowMatrixX3d NodeGraph::node_positions(const RowMatrixX3d& X) const {
  RowMatrixX3d p(n_nodes, 3);
  for (int i = 0; i < n_nodes; ++i) p.row(i) = node_position(X, i);
  return p;
}

SparseMatrix NodeGraph::node_matrix() const {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(2 * n_nodes));
  for (int i = 0; i < n_nodes; ++i) {
    t.emplace_back(i, node_vertices(i, 0), 0.5);
    t.emplace_back(i, node_vertices(i, 1), 0.5);  // primal: the two halves sum to 1
  }
  SparseMatrix P(n_nodes, n_vertices);
  P.setFromTriplets(t.begin(), t.end());
  return P;
}

SparseMatrix NodeGraph::laplacian() const {
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(static_cast<size_t>(4 * arcs.rows()));
  for (Eigen::Index a = 0; a < arcs.rows(); ++a) {
    const int i = arcs(a, 0), j = arcs(a, 1);
    const double w = arc_weights(a);
    t.emplace_back(i, j, -w);
    t.emplace_back(j, i, -w);
    t.emplace_back(i, i, w);
    t.emplace_back(j, j, w);
  }
  SparseMatrix L(n_nodes, n_nodes);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

}  // namespace edgedeform
