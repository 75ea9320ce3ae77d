#include <gtest/gtest.h>

#include <queue>
#include <set>

#include <Eigen/Dense>

#include "edgedeform/coarse_space.h"
#include "edgedeform/edge_topology.h"
#include "edgedeform/node_graph.h"
#include "grid_lift.h"
#include "test_meshes.h"

using namespace edgedeform;
using test::GridLift;

namespace {

Eigen::MatrixXd dense_basis(const CoarseBasis& b) {
  const int nf = static_cast<int>(b.patch.size());
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(3 * nf, b.dimension());
  for (int k = 0; k < b.dimension(); ++k) {
    Eigen::VectorXd q = Eigen::VectorXd::Unit(b.dimension(), k);
    Eigen::MatrixXd x;
    prolong_from_coarse(b, q, x);
    U.col(k) = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  }
  return U;
}

}  // namespace

TEST(CoarseSpace, PatchesCoverTheFreeVerticesAndAreConnected) {
  GridLift s;
  const CoarseBasis b = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 10);
  ASSERT_EQ(b.n_patches, 10);
  ASSERT_EQ(b.patch.size(), static_cast<size_t>(s.system.n_free()));
  // connectivity of each patch through mesh edges between its own vertices
  std::vector<int> local(s.mesh.V.rows(), -1);
  for (int k = 0; k < s.system.n_free(); ++k) local[s.system.free_vertices[k]] = k;
  std::vector<std::vector<int>> adj(s.system.n_free());
  for (Eigen::Index e = 0; e < s.topology.edges.rows(); ++e) {
    const int a = local[s.topology.edges(e, 0)], c = local[s.topology.edges(e, 1)];
    if (a >= 0 && c >= 0 && b.patch[a] == b.patch[c]) {
      adj[a].push_back(c);
      adj[c].push_back(a);
    }
  }
  for (int p = 0; p < b.n_patches; ++p) {
    std::vector<int> members;
    for (int v = 0; v < s.system.n_free(); ++v)
      if (b.patch[v] == p) members.push_back(v);
    ASSERT_FALSE(members.empty());
    std::set<int> seen{members[0]};
    std::queue<int> q;
    q.push(members[0]);
    while (!q.empty()) {
      const int v = q.front();
      q.pop();
      for (int u : adj[v])
        if (seen.insert(u).second) q.push(u);
    }
    EXPECT_EQ(seen.size(), members.size()) << "patch " << p << " is not connected";
  }
}

TEST(CoarseSpace, RestrictionIsTheProlongationsTransposeAndTheBasisHasFullRank) {
  GridLift s;
  const CoarseBasis b = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 12);
  const Eigen::MatrixXd U = dense_basis(b);
  const int nf = s.system.n_free();
  std::srand(3);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(nf, 3);
  Eigen::VectorXd q;
  restrict_to_coarse(b, x, q);
  EXPECT_LE((q - U.transpose() * Eigen::Map<const Eigen::VectorXd>(x.data(), x.size())).norm(), 1e-12 * q.norm());
  Eigen::FullPivLU<Eigen::MatrixXd> lu(U);
  EXPECT_EQ(lu.rank(), b.dimension());
  // the grid is curved (bump 0.3), so patches keep their three axes: 12 unknowns each
  EXPECT_EQ(b.dimension(), 12 * b.n_patches);
}

class CoarseStiffness : public ::testing::TestWithParam<int> {};  // blend steps

TEST_P(CoarseStiffness, IsUTransposeAU) {
  GridLift s;
  const CoarseBasis b = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 6, GetParam());
  const AssembledSystem as = assemble_system(s.system, Eigen::VectorXd::Constant(s.graph.n_nodes, 0.5));
  const int nf = s.system.n_free();
  Eigen::MatrixXd A3 = Eigen::MatrixXd::Zero(3 * nf, 3 * nf);
  const Eigen::MatrixXd A = Eigen::MatrixXd(as.A);
  for (int c = 0; c < 3; ++c) A3.block(c * nf, c * nf, nf, nf) = A;
  const Eigen::MatrixXd U = dense_basis(b);
  const Eigen::MatrixXd expected = U.transpose() * A3 * U;
  const Eigen::MatrixXd got = Eigen::MatrixXd(coarse_stiffness(b, as.A));
  EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
}

INSTANTIATE_TEST_SUITE_P(Blend, CoarseStiffness, ::testing::Values(0, 3));

// The blended basis: a partition of unity over the free vertices (weights sum to one, the
// patches overlap), so U still spans every affine motion exactly and has full rank; with
// no blending it is the disjoint basis, one weight-1 entry per vertex.
TEST(CoarseSpace, BlendedPatchesArePartitionOfUnityAndSpanAffineMotions) {
  GridLift s;
  const int nf = s.system.n_free();
  const CoarseBasis disjoint = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 12, 0);
  ASSERT_EQ(disjoint.entry_patch.size(), static_cast<size_t>(nf));
  for (int v = 0; v < nf; ++v) {
    EXPECT_EQ(disjoint.entry_patch[static_cast<size_t>(v)], disjoint.patch[static_cast<size_t>(v)]);
    EXPECT_EQ(disjoint.entry_value[static_cast<size_t>(v)](0), 1.0);
  }
  const CoarseBasis b = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 12, 4);
  EXPECT_EQ(b.dimension(), disjoint.dimension());
  int shared = 0;
  for (int v = 0; v < nf; ++v) {
    double total = 0.0;
    int last = -1;
    for (int e = b.entry_offset[static_cast<size_t>(v)]; e < b.entry_offset[static_cast<size_t>(v) + 1]; ++e) {
      total += b.entry_value[static_cast<size_t>(e)](0);
      EXPECT_GT(b.entry_patch[static_cast<size_t>(e)], last);  // sorted, no repeats
      last = b.entry_patch[static_cast<size_t>(e)];
    }
    EXPECT_NEAR(total, 1.0, 1e-12);
    shared += b.entry_offset[static_cast<size_t>(v) + 1] - b.entry_offset[static_cast<size_t>(v)] > 1;
  }
  EXPECT_GT(shared, nf / 4);  // the borders are blended
  const Eigen::MatrixXd U = dense_basis(b);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(U);
  EXPECT_EQ(lu.rank(), b.dimension());
  // A global affine motion of the free vertices lies in the span.
  Eigen::Matrix3d M;
  M << 0.3, -1.2, 0.5, 0.7, 0.1, -0.4, 1.1, 0.2, 0.9;
  const Eigen::RowVector3d t(0.2, -0.5, 1.0);
  Eigen::MatrixXd x(nf, 3);
  for (int v = 0; v < nf; ++v) x.row(v) = s.mesh.V.row(s.system.free_vertices[static_cast<size_t>(v)]) * M.transpose() + t;
  const Eigen::VectorXd flat = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  const Eigen::VectorXd fitted = U * U.colPivHouseholderQr().solve(flat);
  EXPECT_LE((fitted - flat).norm(), 1e-10 * flat.norm());
  // restrict is prolong's transpose here too
  Eigen::VectorXd q;
  restrict_to_coarse(b, x, q);
  EXPECT_LE((q - U.transpose() * flat).norm(), 1e-12 * q.norm());
}

TEST(CoarseSpace, TooFewFreeVerticesGiveNoCoarseSpace) {
  std::vector<int> roi;
  for (int i = 0; i < 20; ++i) roi.push_back(i), roi.push_back(19 * 20 + i);
  for (int i = 0; i < 10; ++i) roi.push_back(10 * 20 + i);  // 10 free vertices
  GridLift s(roi);
  ASSERT_EQ(s.system.n_free(), 10);
  const CoarseBasis b = build_coarse_basis(s.system, s.mesh.V, s.topology.edges, 100);
  EXPECT_EQ(b.dimension(), 0);
  CoarseCorrection correction;
  EXPECT_FALSE(correction.factor(b, SparseMatrix(0, 0)));
  Eigen::MatrixXd out;
  correction.apply(Eigen::MatrixXd::Ones(10, 3), out);
  EXPECT_EQ(out.norm(), 0.0);  // no correction, no NaN
}

TEST(CoarseSpace, FlatPatchesDropTheirNormalAxis) {
  test::TestMesh flat = test::grid(12, 12, 0.0);
  const EdgeTopology topology = build_edge_topology(flat.F, static_cast<int>(flat.V.rows()));
  const NodeGraph graph = build_node_graph(flat.V, flat.F, topology, Domain::Primal, true);
  ConstraintSets sets;
  sets.handles = {0};
  sets.statics = {143};
  const ConstrainedSystem sys = build_constrained_system(graph, flat.V, topology.edges, std::vector<bool>(144, true), sets);
  const CoarseBasis b = build_coarse_basis(sys, flat.V, topology.edges, 4);
  for (int p = 0; p < b.n_patches; ++p) EXPECT_EQ(b.functions[p], 3);  // constant + two in-plane axes
  Eigen::FullPivLU<Eigen::MatrixXd> lu(dense_basis(b));
  EXPECT_EQ(lu.rank(), b.dimension());
}
