#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "edgedeform/local_step.h"
#include "edgedeform/node_graph.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

// Reference: Eigen's general SVD and the textbook reflection fix.
Eigen::Matrix3d reference_rotation(const Eigen::Matrix3d& S) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  Eigen::Matrix3d R = svd.matrixV() * U.transpose();
  if (R.determinant() < 0) {
    U.col(2) *= -1;
    R = svd.matrixV() * U.transpose();
  }
  return R;
}

}  // namespace

TEST(ClosestRotation, MatchesTheSvdReferenceOnRandomMatrices) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Matrix3d S;
    for (int k = 0; k < 9; ++k) S.data()[k] = g(rng);
    const Eigen::Matrix3d R = closest_rotation(S);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_LT((R * R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT((R - reference_rotation(S)).norm(), 1e-9) << "trial " << trial;
  }
}

TEST(ClosestRotation, RecoversARotationFromARotatedRankTwoMatrix) {
  // A planar neighbourhood: S = sum w e0 e^T with every e0 in a plane.
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix3d S = Eigen::Matrix3d::Zero();
  const Eigen::Vector3d e0s[3] = {{1, 0, 0}, {0.3, 1, 0}, {-0.7, 0.2, 0}};
  for (const auto& e0 : e0s) S += e0 * (Q * e0).transpose();
  EXPECT_LT((closest_rotation(S) - Q).norm(), 1e-12);
}

TEST(ClosestRotation, IdentityForASymmetricPositiveMatrix) {
  Eigen::Matrix3d S;
  S << 3, 1, 0, 1, 2, 0.5, 0, 0.5, 1;
  EXPECT_LT((closest_rotation(S) - Eigen::Matrix3d::Identity()).norm(), 1e-14);
  EXPECT_LT((closest_rotation(Eigen::Matrix3d::Zero()) - Eigen::Matrix3d::Identity()).norm(), 0.0 + 1e-15);
}

TEST(ClosestRotation, ReflectionIsFixed) {
  Eigen::Matrix3d S = Eigen::Vector3d(3, 2, 1).asDiagonal();
  S(2, 2) = -1;  // det < 0: the best proper rotation flips the smallest axis back
  const Eigen::Matrix3d R = closest_rotation(S);
  EXPECT_LT((R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
}

TEST(FitLocal, RecoversRotationAndScaleOfASimilarity) {
  // A real mesh: a right-angled grid would leave nodes whose only weighted arcs are
  // collinear, where the rotation is not unique.
  const auto m = test::read_off("cgal_dino.off");
  const auto topo = build_edge_topology(m.F, static_cast<int>(m.V.rows()));
  for (Domain d : {Domain::Edge, Domain::Primal}) {
    const auto g = build_node_graph(m.V, m.F, topo, d, true);
    std::vector<int> all(g.n_nodes);
    for (int i = 0; i < g.n_nodes; ++i) all[i] = i;
    const NodeStencil st = build_stencil(g, g.node_positions(m.V), all, all);
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
