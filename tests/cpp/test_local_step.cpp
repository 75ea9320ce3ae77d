#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "local_fit/local_step.h"
#include "mesh/node_graph.h"
#include "test_meshes.h"

using namespace edgedeform;

TEST(FitLocal, RecoversRotationAndScaleOfASimilarity) {
  // A real mesh: a right-angled grid would leave nodes whose only weighted arcs are
  // collinear, where the rotation is not unique.
  const auto m = test::read_off("cgal_dino.off");
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  for (Domain d : {Domain::Edge, Domain::Primal}) {
    const auto g = build_node_graph(m.V, m.F, topo, d, true);
    std::vector<int> all(g.n_nodes);
    for (int i = 0; i < g.n_nodes; ++i) all[i] = i;
    const NodeStencil st = build_stencil(g, m.V, all, all);
    const Eigen::Matrix3d Q = Eigen::AngleAxisd(0.8, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
    const double scale = 1.7;
    const RowMatrixX3d X = (scale * m.V * Q.transpose()).rowwise() + Eigen::RowVector3d(1, -2, 3);
    LocalFit fit;
    fit_local(st, g.node_positions(X), Eigen::VectorXd::Constant(g.n_nodes, 0.5), fit);
    for (int i = 0; i < g.n_nodes; ++i) {
      if (st.rest_norm(i) == 0.0) continue;
      EXPECT_LT((fit.rotation[i] - Q).norm(), 1e-8);  // a few dino nodes are nearly rank 1
      EXPECT_NEAR(fit.scale(i), scale, 1e-10);
    }
    // Rotation and scale explain everything: the Laplacian term is zero, and the rigid term
    // is the scale mismatch (s-1)^2 sum w |e0|^2.
    const Eigen::VectorXd lam1 = Eigen::VectorXd::Ones(g.n_nodes);
    fit_local(st, g.node_positions(X), lam1, fit);
    EXPECT_NEAR(fit.energy, (scale - 1) * (scale - 1) * st.rest_norm.sum(), 1e-9 * st.rest_norm.sum());
    fit_local(st, g.node_positions(X), Eigen::VectorXd::Zero(g.n_nodes), fit);
    EXPECT_LT(fit.energy, 1e-20 * st.rest_norm.sum());
  }
}

TEST(FitLocal, ScaleIsClampedToAPlausibleRange) {
  const auto m = test::read_off("cgal_dino.off");
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  const auto g = build_node_graph(m.V, m.F, topo, Domain::Edge, true);
  std::vector<int> all(g.n_nodes);
  for (int i = 0; i < g.n_nodes; ++i) all[i] = i;
  const NodeStencil st = build_stencil(g, m.V, all, all);
  LocalFit fit;
  fit_local(st, g.node_positions(RowMatrixX3d(6.0 * m.V)), Eigen::VectorXd::Zero(g.n_nodes), fit);
  EXPECT_DOUBLE_EQ(fit.scale.maxCoeff(), kMaxScale);
  fit_local(st, g.node_positions(RowMatrixX3d(0.1 * m.V)), Eigen::VectorXd::Zero(g.n_nodes), fit);
  EXPECT_DOUBLE_EQ(fit.scale.minCoeff(), kMinScale);
}

TEST(FitLocal, ATermsFitDoesNotDependOnItsSimdPartner) {
  // fit_local takes terms two at a time (SIMD lanes). Dropping the first term changes every
  // pairing; each remaining term's fit must stay the same, bit for bit, cold and warm.
  const auto m = test::read_off("cgal_dino.off");
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  for (Domain d : {Domain::Edge, Domain::Primal}) {
    const auto g = build_node_graph(m.V, m.F, topo, d, true);
    std::vector<int> all(g.n_nodes), position(g.n_nodes);
    for (int i = 0; i < g.n_nodes; ++i) all[i] = position[i] = i;
    const std::vector<int> shifted(all.begin() + 1, all.end());
    const NodeStencil st = build_stencil(g, m.V, all, position);
    const NodeStencil st_shifted = build_stencil(g, m.V, shifted, position);
    RowMatrixX3d X = m.V;
    for (Eigen::Index v = 0; v < X.rows(); ++v)  // a bend: rotations vary from node to node
      X.row(v) = Eigen::AngleAxisd(0.5 * m.V(v, 1), Eigen::Vector3d::UnitX()).toRotationMatrix() * m.V.row(v).transpose();
    LocalFit full, part;
    for (double angle : {0.0, 0.02}) {  // cold (SVD), then warm from the first fit (Newton)
      const RowMatrixX3d Y = X * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      fit_local(st, g.node_positions(Y), Eigen::VectorXd::Constant(st.n_terms, 0.5), full);
      fit_local(st_shifted, g.node_positions(Y), Eigen::VectorXd::Constant(st_shifted.n_terms, 0.5), part);
      for (int t = 0; t < st_shifted.n_terms; ++t) {
        ASSERT_EQ(part.rotation[static_cast<size_t>(t)], full.rotation[static_cast<size_t>(t) + 1]) << "term " << t;
        ASSERT_EQ(part.scale(t), full.scale(t + 1));
        ASSERT_EQ(part.term_energy(t), full.term_energy(t + 1));
      }
    }
  }
}
