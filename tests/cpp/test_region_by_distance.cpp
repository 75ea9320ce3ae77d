// region_by_distance.cpp against brute force and bounds, and the cases where straight-line
// and over-the-surface regions differ; constrained_layout's roi_radius against the same roi.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "system/constrained_system.h"
#include "mesh/edge_topology.h"
#include "base/errors.h"
#include "mesh/mesh_checks.h"
#include "mesh/region_by_distance.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// A ladder of unit squares along x at height z: vertices (i, 0, z), (i, 1, z) for i = 0..k,
// appended to m (so that two calls make two components).
void add_strip(test::TestMesh& m, int k, double z) {
  const int v0 = static_cast<int>(m.V.rows()), f0 = static_cast<int>(m.F.rows());
  m.V.conservativeResize(v0 + 2 * (k + 1), 3);
  for (int i = 0; i <= k; ++i) {
    m.V.row(v0 + 2 * i) << i, 0, z;
    m.V.row(v0 + 2 * i + 1) << i, 1, z;
  }
  m.F.conservativeResize(f0 + 2 * k, 3);
  for (int i = 0; i < k; ++i) {
    const int a = v0 + 2 * i, b = a + 1, c = a + 2, d = a + 3;
    m.F.row(f0 + 2 * i) << a, c, d;
    m.F.row(f0 + 2 * i + 1) << a, d, b;
  }
}

RowMatrixX2i edges_of(const test::TestMesh& m) {
  return build_edge_topology(m.F, static_cast<int>(m.V.rows())).edges;
}

std::vector<int> brute_straight_line(const RowMatrixX3d& V, const std::vector<int>& seeds, double r) {
  std::vector<int> out;
  for (int v = 0; v < V.rows(); ++v)
    for (int s : seeds) {
      const double dx = V(v, 0) - V(s, 0), dy = V(v, 1) - V(s, 1), dz = V(v, 2) - V(s, 2);
      if (dx * dx + dy * dy + dz * dz <= r * r) {
        out.push_back(v);
        break;
      }
    }
  return out;
}

// Shortest paths by relaxing every edge until nothing changes (Bellman-Ford).
std::vector<int> brute_along_edges(const RowMatrixX3d& V, const RowMatrixX2i& E, const std::vector<int>& seeds,
                                   double r) {
  std::vector<double> d(static_cast<size_t>(V.rows()), std::numeric_limits<double>::infinity());
  for (int s : seeds) d[static_cast<size_t>(s)] = 0.0;
  for (bool changed = true; changed;) {
    changed = false;
    for (Eigen::Index e = 0; e < E.rows(); ++e) {
      const int a = E(e, 0), b = E(e, 1);
      const double len = (V.row(a) - V.row(b)).norm();
      if (d[static_cast<size_t>(a)] + len < d[static_cast<size_t>(b)]) d[static_cast<size_t>(b)] = d[static_cast<size_t>(a)] + len, changed = true;
      if (d[static_cast<size_t>(b)] + len < d[static_cast<size_t>(a)]) d[static_cast<size_t>(a)] = d[static_cast<size_t>(b)] + len, changed = true;
    }
  }
  std::vector<int> out;
  for (int v = 0; v < V.rows(); ++v)
    if (d[static_cast<size_t>(v)] <= r) out.push_back(v);
  return out;
}

}  // namespace

TEST(RegionByDistance, AVertexExactlyAtTheRadiusIsInside) {
  test::TestMesh m;
  add_strip(m, 4, 0.0);  // vertex 2 i sits at (i, 0, 0): exactly i from vertex 0
  const RowMatrixX2i E = edges_of(m);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  for (bool along : {false, true}) {
    const std::vector<int> at = vertices_within_distance(m.V, A, {0}, 2.0, along);
    EXPECT_NE(std::find(at.begin(), at.end(), 4), at.end()) << along;
    EXPECT_EQ(std::find(at.begin(), at.end(), 6), at.end()) << along;
    const std::vector<int> below = vertices_within_distance(m.V, A, {0}, std::nextafter(2.0, 0.0), along);
    EXPECT_EQ(std::find(below.begin(), below.end(), 4), below.end()) << along;
  }
  // (0, 1) and (1, 0) are 1 away, both ways; (1, 1) is sqrt(2) away, both ways (the diagonal edge).
  for (bool along : {false, true}) EXPECT_EQ(vertices_within_distance(m.V, A, {0}, 1.0, along), (std::vector<int>{0, 1, 2}));
}

TEST(RegionByDistance, AlongTheEdgesStaysOnTheHandlesComponent) {
  test::TestMesh m;
  add_strip(m, 3, 0.0);
  add_strip(m, 3, 0.5);  // a second component half a unit above the first
  const RowMatrixX2i E = edges_of(m);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  const std::vector<int> straight = vertices_within_distance(m.V, A, {0}, 0.6, false);
  const std::vector<int> along = vertices_within_distance(m.V, A, {0}, 0.6, true);
  EXPECT_EQ(straight, (std::vector<int>{0, 8}));  // 8 is vertex 0's twin above it
  EXPECT_EQ(along, (std::vector<int>{0}));
}

TEST(RegionByDistance, AlongTheEdgesAroundAUTurn) {
  // A strip folded into a U: the arms (y in [0, 1] and [3, 4]) joined at x = 4 by a column.
  test::TestMesh m = test::grid(5, 5);
  m.V *= 4.0;  // unit spacing
  std::vector<int> keep_faces;
  for (int f = 0; f < m.F.rows(); ++f) {
    const double cx = (m.V(m.F(f, 0), 0) + m.V(m.F(f, 1), 0) + m.V(m.F(f, 2), 0)) / 3.0;
    const double cy = (m.V(m.F(f, 0), 1) + m.V(m.F(f, 1), 1) + m.V(m.F(f, 2), 1)) / 3.0;
    if (cy < 1.0 || cy > 3.0 || cx > 3.0) keep_faces.push_back(f);
  }
  RowMatrixX3i F(static_cast<Eigen::Index>(keep_faces.size()), 3);
  for (size_t k = 0; k < keep_faces.size(); ++k) F.row(static_cast<Eigen::Index>(k)) = m.F.row(keep_faces[k]);
  m.F = F;
  const RowMatrixX2i E = edges_of(m);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  const int handle = 0, across = 4 * 5;  // (0, 0) and (0, 4): 4 apart, farther along the U
  const std::vector<int> straight = vertices_within_distance(m.V, A, {handle}, 4.0, false);
  const std::vector<int> along = vertices_within_distance(m.V, A, {handle}, 4.0, true);
  EXPECT_NE(std::find(straight.begin(), straight.end(), across), straight.end());
  EXPECT_EQ(std::find(along.begin(), along.end(), across), along.end());
  EXPECT_TRUE(std::includes(straight.begin(), straight.end(), along.begin(), along.end()));
  const std::vector<int> edges = brute_along_edges(m.V, E, {handle}, 4.0);
  EXPECT_TRUE(std::includes(along.begin(), along.end(), edges.begin(), edges.end()));
  const std::vector<int> far = brute_along_edges(m.V, E, {handle}, 12.0);
  EXPECT_NE(std::find(far.begin(), far.end(), across), far.end());
}

bool contains(const std::vector<int>& outer, const std::vector<int>& inner) {
  return std::includes(outer.begin(), outer.end(), inner.begin(), inner.end());
}

TEST(RegionByDistance, StraightLineMatchesBruteForceAndOverTheSurfaceLiesBetweenEdgesAndLine) {
  // The surface distance is at least the chord and at most the path along the edges.
  const test::TestMesh m = test::grid(40, 30, 0.3);
  const RowMatrixX2i E = edges_of(m);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(m.V.rows()) - 1);
  std::uniform_real_distribution<double> radius(0.01, 0.4);
  int wider_than_edges = 0;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<int> seeds(static_cast<size_t>(1 + trial * 7));  // beyond one k-d leaf
    for (int& s : seeds) s = vertex(rng);
    const double r = radius(rng);
    const std::vector<int> line = vertices_within_distance(m.V, A, seeds, r, false);
    EXPECT_EQ(line, brute_straight_line(m.V, seeds, r)) << trial;
    const std::vector<int> surface = vertices_within_distance(m.V, A, seeds, r, true);
    const std::vector<int> edges = brute_along_edges(m.V, E, seeds, r);
    EXPECT_TRUE(contains(surface, edges)) << trial;
    EXPECT_TRUE(contains(line, surface)) << trial;
    wider_than_edges += surface.size() > edges.size();
  }
  EXPECT_GT(wider_than_edges, 10) << "across the faces should reach farther than along the edges";
}

TEST(RegionByDistance, OverAFlatSurfaceIsTheStraightLine) {
  // Unfolded across the faces, a flat mesh's distance is the Euclidean one, from one seed or
  // several (up to round-off: vertices within 1e-9 of the radius are not judged).
  const test::TestMesh m = test::grid(40, 30, 0.0);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> vertex(0, static_cast<int>(m.V.rows()) - 1);
  std::uniform_real_distribution<double> radius(0.05, 0.5);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<int> seeds(static_cast<size_t>(1 + trial % 4));
    for (int& s : seeds) s = vertex(rng);
    const double r = radius(rng);
    const std::vector<int> surface = vertices_within_distance(m.V, A, seeds, r, true);
    for (int v = 0; v < m.V.rows(); ++v) {
      double d = std::numeric_limits<double>::infinity();
      for (int s : seeds) d = std::min(d, (m.V.row(v) - m.V.row(s)).norm());
      if (std::abs(d - r) < 1e-9) continue;
      EXPECT_EQ(std::binary_search(surface.begin(), surface.end(), v), d < r)
          << "trial " << trial << " vertex " << v << " at " << d << " of " << r;
    }
  }
}

TEST(RegionByDistance, RejectsBadRadiiAndSeeds) {
  const test::TestMesh m = test::grid(4, 4);
  const RowMatrixX2i E = edges_of(m);
  const MeshIncidence incidence = mesh_incidence(m.F, static_cast<int>(m.V.rows()));
  const VertexNeighbours A(m.F, incidence);
  for (double r : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW(vertices_within_distance(m.V, A, {0}, r, false), std::invalid_argument) << r;
  EXPECT_THROW(vertices_within_distance(m.V, A, {16}, 1.0, true), std::out_of_range);
  EXPECT_THROW(vertices_within_distance(m.V, A, {-1}, 1.0, false), std::out_of_range);
}

namespace {

struct Layout {
  test::TestMesh mesh = test::grid(9, 9, 0.2);
  EdgeTopology topo = build_edge_topology(mesh.F, static_cast<int>(mesh.V.rows()));
  NodeGraph g = build_node_graph(mesh.V, mesh.F, topo, Domain::Edge, true);
  std::vector<bool> referenced = referenced_vertices(mesh.F, static_cast<int>(mesh.V.rows()));
  MeshIncidence incidence = mesh_incidence(mesh.F, static_cast<int>(mesh.V.rows()));
  VertexNeighbours neighbours() const { return {mesh.F, incidence}; }

  ConstrainedSystem layout(const ConstraintSets& sets) const {
    return constrained_layout(g, mesh.V, neighbours(), referenced, sets);
  }
};

}  // namespace

TEST(RegionByDistance, RadiusLaysOutAsTheSameRoi) {
  const Layout c;
  for (bool along : {false, true}) {
    ConstraintSets by_radius;
    by_radius.handles = {40};     // the centre
    by_radius.statics = {39, 41};  // inside the radius: they stay static
    by_radius.roi_radius = 0.3;
    by_radius.roi_connected = along;
    ConstraintSets by_list;
    by_list.handles = by_radius.handles;
    by_list.statics = by_radius.statics;
    by_list.roi = vertices_within_distance(c.mesh.V, c.neighbours(), {40}, 0.3, along);
    const ConstrainedSystem a = c.layout(by_radius), b = c.layout(by_list);
    EXPECT_EQ(a.free_vertices, b.free_vertices);
    EXPECT_EQ(a.fixed_vertices, b.fixed_vertices);
    EXPECT_EQ(a.term_nodes, b.term_nodes);
    EXPECT_GT(a.n_free(), 0);
    EXPECT_LT(a.n_free(), 81 - 3);
    for (int v : a.free_vertices) EXPECT_TRUE(v != 39 && v != 41);
  }
}

TEST(RegionByDistance, LayoutRejectsMixedOrEmptyRegions) {
  const Layout c;
  ConstraintSets both;
  both.handles = {40};
  both.roi = std::vector<int>{39, 40, 41};
  both.roi_radius = 0.3;
  EXPECT_THROW(c.layout(both), std::invalid_argument);
  ConstraintSets connected_alone;
  connected_alone.handles = {40};
  connected_alone.roi_connected = true;
  EXPECT_THROW(c.layout(connected_alone), std::invalid_argument);
  ConstraintSets too_small;
  too_small.handles = {40};
  too_small.roi_radius = 0.01;  // grid spacing 1/8: only the handle itself
  try {
    c.layout(too_small);
    FAIL() << "no free vertex, no error";
  } catch (const NoFreeVertexError& e) {  // a std::invalid_argument, of its own type
    EXPECT_NE(std::string(e.what()).find("no free vertex within roi_radius 0.01 of the handles: increase the radius"),
              std::string::npos)
        << e.what();
  }
}

TEST(RegionByDistance, NoLargerRadiusIsSuggestedWhereNoneFreesAVertex) {
  const Layout c;
  for (bool along : {false, true}) {
    ConstraintSets held;  // every vertex but the handle static: no radius frees one
    held.handles = {40};
    for (int v = 0; v < static_cast<int>(c.mesh.V.rows()); ++v)
      if (v != 40) held.statics.push_back(v);
    held.roi_radius = 0.01;
    held.roi_connected = along;
    try {
      c.layout(held);
      FAIL() << "no free vertex, no error";
    } catch (const NoFreeVertexError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find("increase the radius"), std::string::npos) << what;
      EXPECT_NE(what.find("so no radius frees one"), std::string::npos) << what;
    }
  }
}
