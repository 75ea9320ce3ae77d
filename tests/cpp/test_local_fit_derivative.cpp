#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "system/constrained_system.h"
#include "mesh/edge_topology.h"
#include "local_fit/local_fit_derivative.h"
#include "mesh/node_graph.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// A bumpy grid bent and stretched: fits away from the identity, scales away from 1.
RowMatrixX3d deformed(const RowMatrixX3d& V) {
  RowMatrixX3d X = V;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const double x = V(v, 0), y = V(v, 1);
    X.row(v) << 1.3 * x + 0.2 * y * y, 0.8 * y + 0.1 * std::sin(4 * x), V(v, 2) + 0.3 * x * y;
  }
  return X;
}

// omega from two rotations: R2 R1^T = I + [omega]x + O(eps^2)
Eigen::Vector3d rotation_change(const Eigen::Matrix3d& R1, const Eigen::Matrix3d& R2) {
  const Eigen::Matrix3d D = R2 * R1.transpose();
  return 0.5 * Eigen::Vector3d(D(2, 1) - D(1, 2), D(0, 2) - D(2, 0), D(1, 0) - D(0, 1));
}

// A bumpy n x n grid's graph in `domain` and the stencil of every node.
struct GridStencil {
  test::TestMesh mesh;
  NodeGraph graph;
  NodeStencil stencil;
  GridStencil(int n, Domain domain) : mesh(test::grid(n, n, 0.2)) {
    const EdgeTopology topology = build_edge_topology(mesh.F, static_cast<int>(mesh.V.rows()));
    graph = build_node_graph(mesh.V, mesh.F, topology, domain, true);
    std::vector<int> all(graph.n_nodes);
    for (int i = 0; i < graph.n_nodes; ++i) all[i] = i;
    stencil = build_stencil(graph, mesh.V, all, all);
  }
};

class LocalFitDerivative : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(LocalFitDerivative, MatchesCentralDifferencesOfTheFit) {
  const GridStencil grid(9, GetParam());
  const test::TestMesh& m = grid.mesh;
  const NodeGraph& graph = grid.graph;
  const NodeStencil& st = grid.stencil;
  const Eigen::VectorXd lambda = Eigen::VectorXd::Constant(st.n_terms, 0.5);
  const RowMatrixX3d p = graph.node_positions(deformed(m.V));
  LocalFit fit;
  fit_local(st, p, lambda, fit);
  const FitLinearization lin = linearize_fit(st, p, fit);
  std::srand(5);
  const RowMatrixX3d dp = RowMatrixX3d::Random(p.rows(), 3);
  RowMatrixX3d omega;
  Eigen::VectorXd dscale;
  differentiate_fit(st, fit, lin, dp, omega, dscale);
  const double eps = 1e-6;
  LocalFit plus, minus;
  fit_local(st, p + eps * dp, lambda, plus);
  fit_local(st, p - eps * dp, lambda, minus);
  double worst_rotation = 0.0, worst_scale = 0.0, size = 0.0;
  int checked = 0;
  for (int t = 0; t < st.n_terms; ++t) {
    // A term whose weighted arcs are collinear (a right or obtuse angle clamps a weight to
    // 0) takes its spin about the main axis from a tie-breaker (local_step.cpp), whose
    // derivative the linearization leaves out (local_fit_derivative.h): not checked here.
    Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
    for (int a = st.offsets[t]; a < st.offsets[t + 1]; ++a)
      S += st.weight[a] * st.rest_edge.row(a).transpose() * (p.row(st.self[t]) - p.row(st.neighbour[a]));
    const Eigen::Vector3d sigma = Eigen::JacobiSVD<Eigen::Matrix3d>(S).singularValues();
    if (sigma(1) < 1e-3 * sigma(0)) continue;
    ++checked;
    const Eigen::Vector3d fd = rotation_change(minus.rotation[t], plus.rotation[t]) / (2 * eps);
    worst_rotation = std::max(worst_rotation, (fd - omega.row(t).transpose()).norm());
    worst_scale = std::max(worst_scale, std::abs((plus.scale(t) - minus.scale(t)) / (2 * eps) - dscale(t)));
    size = std::max(size, fd.norm());
  }
  ASSERT_GT(size, 1e-3);  // the fits do move
  EXPECT_GT(checked, st.n_terms / 2);
  EXPECT_LE(worst_rotation, 1e-5 * size);
  EXPECT_LE(worst_scale, 1e-5 * std::max(1.0, dscale.cwiseAbs().maxCoeff()));
}

TEST_P(LocalFitDerivative, ClampedScalesDoNotMove) {
  const GridStencil grid(7, GetParam());
  const test::TestMesh& m = grid.mesh;
  const NodeGraph& graph = grid.graph;
  const NodeStencil& st = grid.stencil;
  const RowMatrixX3d p = graph.node_positions(6.0 * m.V);  // scale 6 > kMaxScale everywhere
  LocalFit fit;
  fit_local(st, p, Eigen::VectorXd::Zero(st.n_terms), fit);
  const FitLinearization lin = linearize_fit(st, p, fit);
  EXPECT_EQ(lin.scale_gain.cwiseAbs().maxCoeff(), 0.0);
  for (int t = 0; t < st.n_terms; ++t) EXPECT_EQ(fit.scale(t), kMaxScale);
}

TEST(LocalFitDerivative, ATermWithoutRestLengthHasNoResponse) {
  Eigen::Vector3d omega;
  double ds = 1.0;
  fit_response(Eigen::Matrix3d::Identity(), Eigen::Matrix3d::Zero(), 0.0, Eigen::Matrix3d::Ones(), omega, ds);
  EXPECT_EQ(omega.norm(), 0.0);
  EXPECT_EQ(ds, 0.0);
}

INSTANTIATE_TEST_SUITE_P(BothDomains, LocalFitDerivative, ::testing::Values(Domain::Edge, Domain::Primal));
