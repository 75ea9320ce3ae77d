// The dense index code of constrained_system.cpp, property-test style: the column layout
// (free vertices, then the fixed ones the terms touch), and the assembled matrices against
// a dense reference built straight from the energy's definition (docs/design.md §3, "Energy").
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "system/constrained_system.h"
#include "mesh/stiffness.h"
#include "mesh/mesh_checks.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

struct Case {
  test::TestMesh mesh = test::grid(7, 6, 0.3);
  EdgeTopology topo;
  NodeGraph g;
  ConstraintSets sets;
  ConstrainedSystem sys;

  Case(Domain domain, bool with_roi) {
    topo = build_edge_topology(mesh.F, static_cast<int>(mesh.V.rows()));
    g = build_node_graph(mesh.V, mesh.F, topo, domain, true);
    sets.handles = {40, 41};          // top row
    sets.statics = {0, 1, 2, 3, 4, 5};  // bottom row
    if (with_roi) {
      std::vector<int> roi;
      for (int v = 0; v < mesh.V.rows(); ++v)
        if (v % 7 >= 2) roi.push_back(v);  // the two left columns stay out
      sets.roi = roi;
    }
    const MeshIncidence incidence = mesh_incidence(mesh.F, static_cast<int>(mesh.V.rows()));
    sys = build_constrained_system(g, mesh.V, VertexNeighbours(mesh.F, incidence),
                                   referenced_vertices(mesh.F, static_cast<int>(mesh.V.rows())), sets);
  }

  // Global vertex of a local column.
  int vertex(int local) const {
    return local < sys.n_free() ? sys.free_vertices[static_cast<size_t>(local)]
                                : sys.fixed_vertices[static_cast<size_t>(local - sys.n_free())];
  }
};

// Dense J1 (one row per arc of the active terms) and J2 (one row per term) over every vertex.
void dense_reference(const Case& c, Eigen::MatrixXd& J1, Eigen::MatrixXd& J2, std::vector<int>& arc_term) {
  const int n = static_cast<int>(c.mesh.V.rows());
  const NodeStencil& st = c.sys.stencil;
  J1.setZero(st.n_arcs(), n);
  J2.setZero(st.n_terms, n);
  arc_term.assign(static_cast<size_t>(st.n_arcs()), -1);
  for (int t = 0; t < st.n_terms; ++t) {
    const int i = c.sys.term_nodes[static_cast<size_t>(t)];
    for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
      arc_term[static_cast<size_t>(a)] = t;
      const int j = c.sys.stencil_nodes[static_cast<size_t>(st.neighbour[static_cast<size_t>(a)])];
      const double w = st.weight[static_cast<size_t>(a)];
      for (int k = 0; k < 2; ++k) {  // p_i - p_j with p the mean of the node's two vertices
        if (w != 0.0) {
          J1(a, c.g.node_vertices(i, k)) += 0.5;
          J1(a, c.g.node_vertices(j, k)) -= 0.5;
        }
        J2(t, c.g.node_vertices(i, k)) += 0.5 * w;
        J2(t, c.g.node_vertices(j, k)) -= 0.5 * w;
      }
    }
  }
}

Eigen::MatrixXd columns(const Case& c, const Eigen::MatrixXd& M, int first, int count) {
  Eigen::MatrixXd out(M.rows(), count);
  for (int k = 0; k < count; ++k) out.col(k) = M.col(c.vertex(first + k));
  return out;
}

class ConstrainedSystemCases : public ::testing::TestWithParam<std::tuple<Domain, bool>> {};

}  // namespace

TEST_P(ConstrainedSystemCases, ColumnLayoutIsFreeThenFixedAndMapsBackToTheGraph) {
  const auto [domain, with_roi] = GetParam();
  const Case c(domain, with_roi);
  const int n = static_cast<int>(c.mesh.V.rows()), nf = c.sys.n_free(), nc = c.sys.n_fixed();
  std::vector<bool> constrained(static_cast<size_t>(n), false);
  for (int v : c.sets.handles) constrained[static_cast<size_t>(v)] = true;
  for (int v : c.sets.statics) constrained[static_cast<size_t>(v)] = true;
  if (c.sets.roi) {
    std::vector<bool> in(static_cast<size_t>(n), false);
    for (int v : *c.sets.roi) in[static_cast<size_t>(v)] = true;
    for (int v = 0; v < n; ++v) constrained[static_cast<size_t>(v)] = constrained[static_cast<size_t>(v)] || !in[static_cast<size_t>(v)];
  }
  // Free: every unconstrained vertex, ascending; fixed: constrained, each once.
  std::vector<int> expected_free;
  for (int v = 0; v < n; ++v)
    if (!constrained[static_cast<size_t>(v)]) expected_free.push_back(v);
  EXPECT_EQ(c.sys.free_vertices, expected_free);
  std::vector<int> seen(static_cast<size_t>(n), 0);
  for (int v : c.sys.fixed_vertices) {
    EXPECT_TRUE(constrained[static_cast<size_t>(v)]) << v;
    EXPECT_EQ(++seen[static_cast<size_t>(v)], 1) << v;
  }
  if (c.sets.roi) EXPECT_LT(c.sys.n_terms(), c.g.n_nodes);  // the left columns' terms are out
  // Stencil nodes: active terms first; their local vertex columns map back to the graph.
  ASSERT_EQ(c.sys.stencil_node_vertices.rows(), static_cast<Eigen::Index>(c.sys.stencil_nodes.size()));
  for (size_t s = 0; s < c.sys.stencil_nodes.size(); ++s)
    for (int k = 0; k < 2; ++k) {
      const int local = c.sys.stencil_node_vertices(static_cast<Eigen::Index>(s), k);
      ASSERT_GE(local, 0);
      ASSERT_LT(local, nf + nc);
      EXPECT_EQ(c.vertex(local), c.g.node_vertices(c.sys.stencil_nodes[s], k));
    }
  for (int t = 0; t < c.sys.n_terms(); ++t) EXPECT_EQ(c.sys.stencil.self[static_cast<size_t>(t)], t);
  // Every active term touches a free vertex or neighbours a node that does.
  EXPECT_EQ(c.sys.J1f.cols(), nf);
  EXPECT_EQ(c.sys.J1c.cols(), nc);
  EXPECT_EQ(c.sys.J2f.rows(), c.sys.n_terms());
}

TEST_P(ConstrainedSystemCases, JacobiansAndAssembledMatricesMatchADenseReference) {
  const auto [domain, with_roi] = GetParam();
  const Case c(domain, with_roi);
  const int nf = c.sys.n_free(), nc = c.sys.n_fixed();
  Eigen::MatrixXd J1, J2;
  std::vector<int> arc_term;
  dense_reference(c, J1, J2, arc_term);
  EXPECT_LT((Eigen::MatrixXd(c.sys.J1f) - columns(c, J1, 0, nf)).norm(), 1e-14);
  EXPECT_LT((Eigen::MatrixXd(c.sys.J1c) - columns(c, J1, nf, nc)).norm(), 1e-14);
  EXPECT_LT((Eigen::MatrixXd(c.sys.J2f) - columns(c, J2, 0, nf)).norm(), 1e-14);
  EXPECT_LT((Eigen::MatrixXd(c.sys.J2c) - columns(c, J2, nf, nc)).norm(), 1e-14);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::VectorXd vertex_lambda(c.g.n_vertices);
  for (int v = 0; v < c.g.n_vertices; ++v) vertex_lambda(v) = unit(rng);
  AssembledSystem as = assemble_system(c.sys, vertex_lambda);
  for (int pass = 0; pass < 2; ++pass) {  // as assembled, then after update_stiffness
    Eigen::VectorXd W1(J1.rows()), W2(J2.rows());
    for (int a = 0; a < J1.rows(); ++a)
      W1(a) = as.term_lambda(arc_term[static_cast<size_t>(a)]) * c.sys.stencil.weight[static_cast<size_t>(a)];
    for (int t = 0; t < J2.rows(); ++t) {
      EXPECT_EQ(as.term_lambda(t), node_stiffness(c.g, vertex_lambda)(c.sys.term_nodes[static_cast<size_t>(t)]));
      W2(t) = 1.0 - as.term_lambda(t);
    }
    const Eigen::MatrixXd F1 = columns(c, J1, 0, nf), F2 = columns(c, J2, 0, nf);
    const Eigen::MatrixXd A = F1.transpose() * W1.asDiagonal() * F1 + F2.transpose() * W2.asDiagonal() * F2;
    const Eigen::MatrixXd K = F1.transpose() * W1.asDiagonal() * columns(c, J1, nf, nc) +
                              F2.transpose() * W2.asDiagonal() * columns(c, J2, nf, nc);
    EXPECT_LT((Eigen::MatrixXd(as.A) - A).norm(), 1e-12 * A.norm()) << pass;
    EXPECT_LT((Eigen::MatrixXd(as.K_fixed) - K).norm(), 1e-12 * A.norm()) << pass;
    for (int v = 0; v < c.g.n_vertices; ++v) vertex_lambda(v) = unit(rng);
    update_stiffness(as, c.sys, vertex_lambda);
  }
}

INSTANTIATE_TEST_SUITE_P(DomainsAndRegion, ConstrainedSystemCases,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal), ::testing::Bool()),
                         [](const auto& info) {
                           return std::string(domain_name(std::get<0>(info.param))) +
                                  (std::get<1>(info.param) ? "_roi" : "_whole");
                         });

TEST(FreeVertexOrder, SortsByRankAndRefusesUnrankedVertices) {
  const Case c(Domain::Edge, false);
  const int n = static_cast<int>(c.mesh.V.rows());
  std::vector<int> rank(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) rank[static_cast<size_t>(v)] = (v * 17) % n;  // a permutation (n = 42, gcd 1)
  const std::vector<int> order = free_vertex_order(c.sys, rank);
  ASSERT_EQ(order.size(), static_cast<size_t>(c.sys.n_free()));
  for (size_t k = 1; k < order.size(); ++k)
    EXPECT_LT(rank[static_cast<size_t>(c.sys.free_vertices[static_cast<size_t>(order[k - 1])])],
              rank[static_cast<size_t>(c.sys.free_vertices[static_cast<size_t>(order[k])])]);
  rank[static_cast<size_t>(c.sys.free_vertices[3])] = -1;
  EXPECT_TRUE(free_vertex_order(c.sys, rank).empty());
  EXPECT_TRUE(free_vertex_order(c.sys, {}).empty());
}
