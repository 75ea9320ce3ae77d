#include <gtest/gtest.h>

#include <cmath>

#include "mesh/cotangent.h"
#include "mesh/node_graph.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {
NodeGraph graph_of(const test::TestMesh& m, Domain d, bool clamp = true) {
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  return build_node_graph(m.V, m.F, topo, d, clamp);
}
}  // namespace

TEST(Cotangent, RightAndEquilateralAngles) {
  EXPECT_NEAR(safe_cotangent({1, 0, 0}, {0, 1, 0}), 0.0, 1e-15);
  EXPECT_NEAR(safe_cotangent({1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}), 1.0 / std::sqrt(3.0), 1e-15);
}

TEST(Cotangent, FiniteForNeedleAndZeroAreaTriangles) {
  const double needle = safe_cotangent({1, 0, 0}, {1, 1e-14, 0});
  EXPECT_TRUE(std::isfinite(needle));
  EXPECT_LE(needle, 1.0 / kSinFloor + 1e-6);
  EXPECT_TRUE(std::isfinite(safe_cotangent({1, 0, 0}, {2, 0, 0})));
  EXPECT_TRUE(std::isfinite(safe_cotangent({1, 0, 0}, {-2, 0, 0})));
  EXPECT_EQ(safe_cotangent({0, 0, 0}, {1, 0, 0}), 0.0);
}

TEST(NodeGraph, SingleTriangleEdgeDomainWeightsAreHalfCotangents) {
  test::TestMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 2, 0, 0, 0, 1, 0;  // right angle at vertex 0
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  const auto g = graph_of(m, Domain::Edge);
  ASSERT_EQ(g.n_nodes, 3);
  ASSERT_EQ(g.arcs.rows(), 3);
  // Edges sorted: (0,1)=0, (0,2)=1, (1,2)=2. The arc of nodes 0 and 1 meets at vertex 0.
  for (Eigen::Index a = 0; a < 3; ++a) {
    const int i = g.arcs(a, 0), j = g.arcs(a, 1);
    double expected = 0.0;
    if (i == 0 && j == 1) expected = 0.0;                  // angle 90 degrees at vertex 0
    if (i == 0 && j == 2) expected = 0.5 * (2.0 / 1.0);    // at vertex 1: cot = 2/1
    if (i == 1 && j == 2) expected = 0.5 * (1.0 / 2.0);    // at vertex 2: cot = 1/2
    EXPECT_NEAR(g.arc_weights(a), expected, 1e-14) << i << "," << j;
  }
}

TEST(NodeGraph, InteriorEdgeNodesHaveFourNeighbours) {
  const auto m = test::grid(7, 6, 0.3);
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  const auto g = build_node_graph(m.V, m.F, topo, Domain::Edge, true);
  for (int i = 0; i < g.n_nodes; ++i) {
    const int degree = g.offsets[i + 1] - g.offsets[i];
    EXPECT_EQ(degree, topo.face_count(i) == 2 ? 4 : 2);
  }
}

TEST(NodeGraph, NonManifoldEdgeNodeJoinsTheOtherEdgesOfAllItsFaces) {
  const auto m = test::grid_with_fin(6, 5);
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  const auto g = build_node_graph(m.V, m.F, topo, Domain::Edge, /*clamp_negative_weights=*/false);
  int fin_edges = 0;
  for (int i = 0; i < g.n_nodes; ++i) {
    EXPECT_EQ(g.offsets[i + 1] - g.offsets[i], 2 * topo.face_count(i)) << "node " << i;
    fin_edges += topo.face_count(i) == 3;
  }
  EXPECT_EQ(fin_edges, 6 - 1);
  // Each arc weight is still 1/2 cot of the face angle between the two edges: the rows of
  // L sum to zero and the weights of one face are those of a lone triangle.
  const Eigen::VectorXd rows = g.laplacian() * Eigen::VectorXd::Ones(g.n_nodes);
  EXPECT_LT(rows.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(NodeGraph, LaplacianIsSymmetricWithZeroRowSums) {
  const auto m = test::grid(6, 6, 0.5);
  for (Domain d : {Domain::Edge, Domain::Primal}) {
    const SparseMatrix L = graph_of(m, d).laplacian();
    EXPECT_NEAR((SparseMatrix(L.transpose()) - L).norm(), 0.0, 1e-14);
    const Eigen::VectorXd rows = L * Eigen::VectorXd::Ones(L.cols());
    EXPECT_LT(rows.cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(NodeGraph, PrimalWeightsOnAFlatGridArePositive) {
  const auto g = graph_of(test::grid(5, 5), Domain::Primal);
  EXPECT_GE(g.arc_weights.minCoeff(), 0.0);
  EXPECT_GT(g.arc_weights.maxCoeff(), 0.0);
}

TEST(NodeGraph, ClampingOnlyChangesNegativeWeights) {
  test::TestMesh m;  // an obtuse triangle pair gives a negative primal weight
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 4, 0, 0, 2, 0.3, 0, 2, -0.3, 0;
  m.F.resize(2, 3);
  m.F << 0, 1, 2, 1, 0, 3;
  const auto signed_graph = graph_of(m, Domain::Primal, false);
  const auto clamped = graph_of(m, Domain::Primal, true);
  ASSERT_LT(signed_graph.arc_weights.minCoeff(), 0.0);
  EXPECT_EQ(clamped.arc_weights, signed_graph.arc_weights.cwiseMax(0.0));
}

TEST(NodeGraph, NodeMatrixTakesMidpoints) {
  const auto m = test::grid(4, 3, 0.2);
  const auto g = graph_of(m, Domain::Edge);
  const RowMatrixX3d p = g.node_matrix() * m.V;
  EXPECT_LT((p - g.node_positions(m.V)).cwiseAbs().maxCoeff(), 1e-15);
  const auto gp = graph_of(m, Domain::Primal);
  EXPECT_LT((RowMatrixX3d(gp.node_matrix() * m.V) - m.V).cwiseAbs().maxCoeff(), 1e-15);
}
