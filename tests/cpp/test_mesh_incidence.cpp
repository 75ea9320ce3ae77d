// The faces around each vertex and the edge numbering the Deformer keeps instead of the edge
// topology: they must name every edge as build_edge_topology does.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "mesh/edge_topology.h"
#include "mesh/mesh_incidence.h"
#include "test_meshes.h"

using namespace edgedeform;

TEST(MeshIncidence, FacesAroundEachVertexAscendAndAreComplete) {
  const test::TestMesh m = test::messy_mesh();
  const int n = static_cast<int>(m.V.rows());
  const MeshIncidence inc = mesh_incidence(m.F, n);
  ASSERT_EQ(inc.n_vertices(), n);
  for (int v = 0; v < n; ++v) {
    std::vector<int> expected;
    for (int f = 0; f < m.F.rows(); ++f)
      if (m.F(f, 0) == v || m.F(f, 1) == v || m.F(f, 2) == v) expected.push_back(f);
    const std::vector<int> got(inc.faces.begin() + inc.face_offsets[static_cast<size_t>(v)],
                               inc.faces.begin() + inc.face_offsets[static_cast<size_t>(v) + 1]);
    EXPECT_EQ(got, expected) << v;
  }
}

TEST(MeshIncidence, EdgeIdsAreTheTopologysRows) {
  for (const test::TestMesh& m : {test::messy_mesh(), test::grid(9, 7, 0.2), test::tetrahedron()}) {
    const int n = static_cast<int>(m.V.rows());
    const EdgeTopology topo = build_edge_topology(m.F, n);
    const MeshIncidence inc = mesh_incidence(m.F, n);
    const VertexNeighbours neighbours(m.F, inc);
    ASSERT_EQ(inc.n_edges(), topo.edges.rows());
    for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
      EXPECT_EQ(neighbours.edge_id(topo.edges(e, 0), topo.edges(e, 1)), e);
      EXPECT_EQ(neighbours.edge_id(topo.edges(e, 1), topo.edges(e, 0)), e);
    }
    // Two vertices no face joins.
    std::vector<int> ring;
    neighbours.sorted(0, ring);
    for (int u = 1; u < n; ++u)
      if (!std::binary_search(ring.begin(), ring.end(), u)) EXPECT_EQ(neighbours.edge_id(0, u), -1) << u;
  }
}

TEST(MeshIncidence, NeighboursAreTheEdgesEndpoints) {
  const test::TestMesh m = test::messy_mesh();
  const int n = static_cast<int>(m.V.rows());
  const EdgeTopology topo = build_edge_topology(m.F, n);
  const MeshIncidence inc = mesh_incidence(m.F, n);
  const VertexNeighbours neighbours(m.F, inc);
  std::vector<std::vector<int>> expected(static_cast<size_t>(n));
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    expected[static_cast<size_t>(topo.edges(e, 0))].push_back(topo.edges(e, 1));
    expected[static_cast<size_t>(topo.edges(e, 1))].push_back(topo.edges(e, 0));
  }
  std::vector<int> ring;
  for (int v = 0; v < n; ++v) {
    std::sort(expected[static_cast<size_t>(v)].begin(), expected[static_cast<size_t>(v)].end());
    neighbours.sorted(v, ring);
    EXPECT_EQ(ring, expected[static_cast<size_t>(v)]) << v;
    std::vector<int> visited;
    neighbours.for_each(v, [&](int u) { visited.push_back(u); });
    std::sort(visited.begin(), visited.end());
    visited.erase(std::unique(visited.begin(), visited.end()), visited.end());
    EXPECT_EQ(visited, ring) << v;
  }
  EXPECT_TRUE(expected.back().empty());  // the unreferenced vertex
}
