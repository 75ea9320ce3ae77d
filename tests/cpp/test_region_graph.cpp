// A region's own graph (built from the faces around it) must lay out the same system as the
// whole mesh's graph, bit for bit: same terms, stencil, weights and rest edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "system/constrained_system.h"
#include "mesh/edge_topology.h"
#include "mesh/mesh_checks.h"
#include "mesh/region_graph.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// Roles with `free` (ascending) free and every other vertex at rest.
VertexRoles roles_freeing(int n, const std::vector<int>& free) {
  VertexRoles roles;
  roles.role.assign(static_cast<size_t>(n), kAtRest);
  for (int v : free) roles.role[static_cast<size_t>(v)] = kFree;
  roles.free_vertices = free;
  return roles;
}

void expect_same_layout(const ConstrainedSystem& a, const ConstrainedSystem& b) {
  EXPECT_EQ(a.free_vertices, b.free_vertices);
  EXPECT_EQ(a.fixed_vertices, b.fixed_vertices);
  EXPECT_EQ(a.term_nodes, b.term_nodes);
  EXPECT_EQ(a.stencil_nodes, b.stencil_nodes);
  EXPECT_EQ(a.stencil_node_vertices, b.stencil_node_vertices);
  EXPECT_EQ(a.stencil.self, b.stencil.self);
  EXPECT_EQ(a.stencil.offsets, b.stencil.offsets);
  EXPECT_EQ(a.stencil.neighbour, b.stencil.neighbour);
  EXPECT_EQ(a.stencil.weight, b.stencil.weight);  // exact: the same sums in the same order
  EXPECT_EQ(a.stencil.rest_edge, b.stencil.rest_edge);
  EXPECT_EQ(a.stencil.rest_laplacian, b.stencil.rest_laplacian);
  EXPECT_EQ(a.stencil.rest_norm, b.stencil.rest_norm);
  EXPECT_EQ(a.rest_scale, b.rest_scale);
}

class RegionGraphCase : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(RegionGraphCase, LaysOutTheWholeGraphsSystemBitForBit) {
  const Domain domain = GetParam();
  for (const test::TestMesh& m : {test::messy_mesh(), test::grid(30, 25, 0.3)}) {
    const int n = static_cast<int>(m.V.rows());
    const NodeGraph whole = build_node_graph(m.V, m.F, build_edge_topology(m.F, n), domain, true);
    const MeshIncidence incidence = mesh_incidence(m.F, n);
    const VertexNeighbours neighbours(m.F, incidence);
    const std::vector<bool> referenced = referenced_vertices(m.F, n);
    std::mt19937 rng(3);
    for (int trial = 0; trial < 12; ++trial) {
      // A ball around a random vertex (contiguous, as a radius picks), or scattered vertices.
      std::vector<int> free;
      const int centre = std::uniform_int_distribution<int>(0, n - 1)(rng);
      const double r = 0.05 + 0.04 * trial;
      for (int v = 0; v < n; ++v) {
        const bool pick = trial % 3 == 2 ? std::bernoulli_distribution(0.1)(rng) : (m.V.row(v) - m.V.row(centre)).norm() <= r;
        if (pick && referenced[static_cast<size_t>(v)]) free.push_back(v);
      }
      if (free.empty()) continue;
      const std::vector<int> faces = faces_around(neighbours, free);
      EXPECT_TRUE(std::is_sorted(faces.begin(), faces.end()));
      const RegionGraph region = region_graph(m.V, neighbours, faces, domain, true);
      EXPECT_TRUE(std::is_sorted(region.nodes.begin(), region.nodes.end()));
      const ConstraintSets sets;
      const ConstrainedSystem from_region = layout_on(region.part(), roles_freeing(n, free), sets);
      const ConstrainedSystem from_whole = layout_on(GraphPart{&whole, &m.V}, roles_freeing(n, free), sets);
      expect_same_layout(from_region, from_whole);
      EXPECT_LT(region.graph.n_nodes, whole.n_nodes) << "trial " << trial << ": the region should be a part";
    }
  }
}

TEST_P(RegionGraphCase, ItsNodesCarryTheWholeGraphsIdsAndVertices) {
  const Domain domain = GetParam();
  const test::TestMesh m = test::messy_mesh();
  const int n = static_cast<int>(m.V.rows());
  const NodeGraph whole = build_node_graph(m.V, m.F, build_edge_topology(m.F, n), domain, true);
  const MeshIncidence incidence = mesh_incidence(m.F, n);
  const VertexNeighbours neighbours(m.F, incidence);
  const RegionGraph region = region_graph(m.V, neighbours, faces_around(neighbours, {m.F(3, 0), m.F(3, 1)}), domain, true);
  ASSERT_GT(region.graph.n_nodes, 0);
  for (int i = 0; i < region.graph.n_nodes; ++i) {
    const int g = region.nodes[static_cast<size_t>(i)];
    for (int c = 0; c < 2; ++c)
      EXPECT_EQ(region.vertices[static_cast<size_t>(region.graph.node_vertices(i, c))], whole.node_vertices(g, c));
  }
  for (Eigen::Index v = 0; v < region.rest.rows(); ++v)
    EXPECT_EQ(region.rest.row(v), m.V.row(region.vertices[static_cast<size_t>(v)]));
}

INSTANTIATE_TEST_SUITE_P(Domains, RegionGraphCase, ::testing::Values(Domain::Edge, Domain::Primal));
