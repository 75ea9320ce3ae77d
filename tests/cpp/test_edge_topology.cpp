#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "mesh/edge_topology.h"
#include "test_meshes.h"

using namespace edgedeform;

TEST(EdgeTopology, TetrahedronHasSixInteriorEdges) {
  const auto m = test::tetrahedron();
  const auto t = build_edge_topology(m.F, 4);
  ASSERT_EQ(t.edges.rows(), 6);
  for (Eigen::Index e = 0; e < 6; ++e) {
    EXPECT_LT(t.edges(e, 0), t.edges(e, 1));
    EXPECT_EQ(t.face_count(e), 2);
  }
}

TEST(EdgeTopology, FaceEdgeIsOppositeItsCorner) {
  const auto m = test::grid(5, 4);
  const auto t = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int e = t.face_edges(f, k);
      const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
      EXPECT_EQ(t.edges(e, 0), std::min(a, b));
      EXPECT_EQ(t.edges(e, 1), std::max(a, b));
    }
}

TEST(EdgeTopology, EulerCountOnAGrid) {
  const auto m = test::grid(6, 5);
  const auto t = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  // V - E + F = 1 for a disc.
  EXPECT_EQ(m.V.rows() - t.edges.rows() + m.F.rows(), 1);
  int boundary = 0;
  for (Eigen::Index e = 0; e < t.edges.rows(); ++e) boundary += t.face_count(e) == 1;
  EXPECT_EQ(boundary, 2 * (6 - 1) + 2 * (5 - 1));
}

TEST(EdgeTopology, NonManifoldEdgeKeepsAllItsFaces) {
  // Three triangles on edge (0, 1): a fin.
  RowMatrixX3i F(3, 3);
  F << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const auto t = build_edge_topology(F, 5);
  ASSERT_EQ(t.edges.rows(), 7);
  EXPECT_EQ(t.edges(0, 0), 0);
  EXPECT_EQ(t.edges(0, 1), 1);
  EXPECT_EQ(t.face_count(0), 3);
  for (int f = 0; f < 3; ++f) {
    int opposite = -1;  // the corner opposite edge (0, 1)
    for (int k = 0; k < 3; ++k)
      if (F(f, k) != 0 && F(f, k) != 1) opposite = k;
    EXPECT_EQ(t.face_edges(f, opposite), 0) << "face " << f;
  }
}

// The edges come out in lexicographic order and each face corner names its opposite edge,
// on a mesh whose vertex ids are shuffled (the grouping by first vertex must not rely on
// faces listing their vertices in order).
TEST(EdgeTopology, EdgesAscendAndMatchTheirCornersWithShuffledIds) {
  auto m = test::grid(23, 17);
  const int n = static_cast<int>(m.V.rows());
  std::vector<int> id(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) id[static_cast<size_t>(v)] = (v * 7919) % n;  // 7919 is prime, n = 391 is not its multiple
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) m.F(f, k) = id[static_cast<size_t>(m.F(f, k))];
  const auto t = build_edge_topology(m.F, n);
  for (Eigen::Index e = 1; e < t.edges.rows(); ++e) {
    const auto prev = std::make_pair(t.edges(e - 1, 0), t.edges(e - 1, 1));
    EXPECT_LT(prev, std::make_pair(t.edges(e, 0), t.edges(e, 1))) << e;
  }
  for (Eigen::Index f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
      const int e = t.face_edges(f, k);
      EXPECT_EQ(t.edges(e, 0), std::min(a, b));
      EXPECT_EQ(t.edges(e, 1), std::max(a, b));
    }
  EXPECT_EQ(m.V.rows() - t.edges.rows() + m.F.rows(), 1);
}
