#include <gtest/gtest.h>

#include <stdexcept>

#include "mesh/node_graph.h"
#include "mesh/stiffness.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {
NodeGraph graph_of(const test::TestMesh& m, Domain d) {
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  return build_node_graph(m.V, m.F, topo, d, true);
}
}  // namespace

TEST(Stiffness, EdgeNodesTakeTheMeanOfTheirEndpoints) {
  const auto m = test::grid(3, 3);
  const auto g = graph_of(m, Domain::Edge);
  Eigen::VectorXd lam = Eigen::VectorXd::LinSpaced(9, 0.0, 1.0);
  const Eigen::VectorXd node = node_stiffness(g, lam);
  for (int i = 0; i < g.n_nodes; ++i)
    EXPECT_DOUBLE_EQ(node(i), 0.5 * (lam(g.node_vertices(i, 0)) + lam(g.node_vertices(i, 1))));
  lam(4) = 1.5;
  EXPECT_THROW(check_stiffness(lam, 9), std::invalid_argument);
  EXPECT_THROW(check_stiffness(Eigen::VectorXd::Zero(8), 9), std::invalid_argument);
}

TEST(Stiffness, SimilarityShareIsTheFloorAboveLambdaAndNeverNegative) {
  Eigen::VectorXd lam(5);
  lam << 0.0, 0.004, 0.01, 0.5, 1.0;
  const double floor = similarity_floor(Domain::Primal);
  ASSERT_DOUBLE_EQ(floor, kPrimalSimilarityFloor);
  const Eigen::VectorXd share = similarity_share(lam, floor);
  ASSERT_EQ(share.size(), 5);
  EXPECT_DOUBLE_EQ(share(0), kPrimalSimilarityFloor);          // lambda 0 keeps the whole floor
  EXPECT_DOUBLE_EQ(share(1), kPrimalSimilarityFloor - 0.004);  // below the floor: the difference
  EXPECT_EQ(share(2), 0.0);                                    // at the floor: none
  EXPECT_EQ(share(3), 0.0);                                    // above: none, not negative
  EXPECT_EQ(share(4), 0.0);
  // The edge domain has no floor, so no term takes a similarity share.
  EXPECT_EQ(similarity_floor(Domain::Edge), 0.0);
  EXPECT_EQ(similarity_share(lam, similarity_floor(Domain::Edge)).cwiseAbs().maxCoeff(), 0.0);
}
