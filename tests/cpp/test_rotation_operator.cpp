// The right-hand-side operator: its column layout (six columns per term), and the operator
// of an assembled system against the right side assembled directly from the energy.
#include <algorithm>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <random>
#include <stdexcept>

#include "system/constrained_system.h"
#include "mesh/mesh_checks.h"
#include "system/rotation_operator.h"
#include "mesh/stiffness.h"
#include "test_meshes.h"

using namespace edgedeform;

namespace {

std::vector<Eigen::Matrix3d> random_rotations(int n, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  std::vector<Eigen::Matrix3d> out;
  for (int t = 0; t < n; ++t)
    out.push_back(Eigen::Quaterniond(normal(rng), normal(rng), normal(rng), normal(rng)).normalized().toRotationMatrix());
  return out;
}

Eigen::VectorXd random_vector(int n, double lo, double hi, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(lo, hi);
  Eigen::VectorXd v(n);
  for (int k = 0; k < n; ++k) v(k) = u(rng);
  return v;
}

}  // namespace

TEST(RotationOperator, AppliesTheSixColumnLayoutOfH) {
  // y = c + H Z, Z(6t+k, d) = lambda_t R_t(d,k), Z(6t+3+k, d) = (1 - lambda_t) s_t R_t(d,k).
  std::mt19937 rng(3);
  const int rows = 9, terms = 5;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < rows; ++r)
    for (int col = 0; col < 6 * terms; ++col)
      if ((r * 7 + col * 3) % 5 == 0) entries.emplace_back(r, col, u(rng));  // scattered, some rows sparse
  SparseMatrixRowMajor H(rows, 6 * terms);
  H.setFromTriplets(entries.begin(), entries.end());
  RotationOperator op(H);
  EXPECT_EQ(op.rows(), rows);
  EXPECT_EQ(op.terms(), terms);

  const auto R = random_rotations(terms, rng);
  const Eigen::VectorXd s = random_vector(terms, 0.5, 2.0, rng), lambda = random_vector(terms, 0.0, 1.0, rng);
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(rows, 3);
  for (bool weighted : {false, true}) {  // every lambda_t starts at 1
    if (weighted) op.set_term_lambda(lambda);
    Eigen::MatrixXd Z(6 * terms, 3);
    for (int t = 0; t < terms; ++t) {
      const double l = weighted ? lambda(t) : 1.0;
      for (int k = 0; k < 3; ++k) {
        Z.row(6 * t + k) = l * R[static_cast<size_t>(t)].col(k).transpose();
        Z.row(6 * t + 3 + k) = (1.0 - l) * s(t) * R[static_cast<size_t>(t)].col(k).transpose();
      }
    }
    Eigen::MatrixXd y;
    op.apply(R, s, c, y);
    const Eigen::MatrixXd expected = c + Eigen::MatrixXd(H) * Z;
    EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-13) << weighted;
  }
  EXPECT_THROW(op.set_term_lambda(Eigen::VectorXd::Ones(terms + 1)), std::invalid_argument);
}

TEST(RotationOperator, RestrictedKeepsTheChosenRowsWithTermsRenumbered) {
  // Rows 6, 1, 4 of a 9 x 5-term H (term 3 dropped; a block of it is only in other rows).
  std::mt19937 rng(5);
  const int rows = 9, terms = 5;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < rows; ++r)
    for (int col = 0; col < 6 * terms; ++col)
      if (col / 6 != 3 || r % 3 == 0) entries.emplace_back(r, col, u(rng));
  SparseMatrixRowMajor H(rows, 6 * terms);
  H.setFromTriplets(entries.begin(), entries.end());
  const RotationOperator op(H);
  const std::vector<int> kept_rows{7, 1, 4}, term_map{0, 1, 2, -1, 3};
  RotationOperator part = op.restricted(kept_rows, term_map, 4);
  EXPECT_EQ(part.rows(), 3);
  EXPECT_EQ(part.terms(), 4);
  const auto R = random_rotations(4, rng);
  const Eigen::VectorXd s = random_vector(4, 0.5, 2.0, rng), lambda = random_vector(4, 0.0, 1.0, rng);
  part.set_term_lambda(lambda);
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(6 * terms, 3);  // the dropped term's rows stay 0
  for (int t = 0; t < terms; ++t) {
    const int k4 = term_map[static_cast<size_t>(t)];
    if (k4 < 0) continue;
    for (int k = 0; k < 3; ++k) {
      Z.row(6 * t + k) = lambda(k4) * R[static_cast<size_t>(k4)].col(k).transpose();
      Z.row(6 * t + 3 + k) = (1.0 - lambda(k4)) * s(k4) * R[static_cast<size_t>(k4)].col(k).transpose();
    }
  }
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(3, 3), dense = Eigen::MatrixXd(H) * Z;
  Eigen::MatrixXd y;
  part.apply(R, s, c, y);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT((y.row(k) - c.row(k) - dense.row(kept_rows[static_cast<size_t>(k)])).cwiseAbs().maxCoeff(), 1e-13) << k;
  EXPECT_THROW(op.restricted({3}, term_map, 4), std::invalid_argument);  // row 3 uses term 3
  EXPECT_THROW(op.restricted({9}, term_map, 4), std::out_of_range);
  EXPECT_THROW(op.restricted({1}, {0, 1, 2}, 3), std::invalid_argument);
}

TEST(RotationOperator, AssembledOperatorMatchesTheRightSideOfTheEnergy) {
  // rhs = J1f^T W1 [R_t(a) e0_a]_a + J2f^T W2 [s_t R_t delta0_t]_t - K_fixed x_c, the
  // right side of the global step's normal equations, for random rotations, scales and
  // per-term lambda, in both domains, before and after a change of lambda; with and without
  // a similarity floor phi_t = max(floor - lambda_t, 0) (stiffness.h), which moves phi_t of
  // the Laplacian weight to the 1-form term with s_t R_t in place of R_t. A matches too:
  // J1f^T W1 J1f + J2f^T W2 J2f with W1 = (lambda + phi) w, W2 = 1 - lambda - phi.
  const test::TestMesh m = test::read_off("cgal_dino.off");
  const int n = static_cast<int>(m.V.rows());
  const EdgeTopology topo = build_edge_topology(m.F, n);
  const MeshIncidence incidence = mesh_incidence(m.F, n);
  std::mt19937 rng(11);
  for (double floor : {0.0, 0.3})
  for (Domain domain : {Domain::Edge, Domain::Primal}) {
    const NodeGraph g = build_node_graph(m.V, m.F, topo, domain, true);
    ConstraintSets sets;
    for (int v = 0; v < n; ++v) {
      if (m.V(v, 2) < m.V.col(2).minCoeff() + 0.1) sets.statics.push_back(v);
      if (m.V(v, 2) > m.V.col(2).maxCoeff() - 0.1) sets.handles.push_back(v);
    }
    ConstrainedSystem sys = build_constrained_system(g, m.V, VertexNeighbours(m.F, incidence), referenced_vertices(m.F, n), sets);
    EXPECT_EQ(sys.similarity_floor, similarity_floor(domain));
    sys.similarity_floor = floor;
    const NodeStencil& st = sys.stencil;
    const int T = st.n_terms;
    AssembledSystem as = assemble_system(sys, random_vector(g.n_vertices, 0.0, 1.0, rng));
    const auto R = random_rotations(T, rng);
    const Eigen::VectorXd s = random_vector(T, 0.5, 2.0, rng);
    const Eigen::MatrixXd xc = Eigen::MatrixXd::Random(sys.n_fixed(), 3);
    for (int pass = 0; pass < 2; ++pass) {
      Eigen::MatrixXd Y1(st.n_arcs(), 3), Y2(T, 3);
      Eigen::VectorXd W1(st.n_arcs()), W2(T);
      for (int t = 0; t < T; ++t) {
        const double lambda = as.term_lambda(t), phi = std::max(floor - lambda, 0.0);
        EXPECT_EQ(as.term_similar(t), phi);
        for (int a = st.offsets[static_cast<size_t>(t)]; a < st.offsets[static_cast<size_t>(t) + 1]; ++a) {
          W1(a) = (lambda + phi) * st.weight[static_cast<size_t>(a)];
          Y1.row(a) = (lambda + phi * s(t)) * st.weight[static_cast<size_t>(a)] *
                      (R[static_cast<size_t>(t)] * st.rest_edge.row(a).transpose()).transpose();
        }
        W2(t) = 1.0 - lambda - phi;
        Y2.row(t) = W2(t) * s(t) * (R[static_cast<size_t>(t)] * st.rest_laplacian.row(t).transpose()).transpose();
      }
      const Eigen::MatrixXd A_expected = Eigen::MatrixXd(SparseMatrix(sys.J1f.transpose()) * W1.asDiagonal() * sys.J1f) +
                                         Eigen::MatrixXd(SparseMatrix(sys.J2f.transpose()) * W2.asDiagonal() * sys.J2f);
      EXPECT_LT((Eigen::MatrixXd(as.A) - A_expected).cwiseAbs().maxCoeff(), 1e-12 * A_expected.cwiseAbs().maxCoeff())
          << domain_name(domain) << " pass " << pass << " floor " << floor;
      const Eigen::MatrixXd c = -(as.K_fixed * xc);
      // sparse products: J1f, J2f themselves are checked against a dense reference elsewhere
      const Eigen::MatrixXd expected = sys.J1f.transpose() * Y1 + sys.J2f.transpose() * Y2 + c;
      Eigen::MatrixXd y;
      as.H.apply(R, s, c, y);
      EXPECT_LT((y - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff())
          << domain_name(domain) << " pass " << pass << " floor " << floor;
      update_stiffness(as, sys, random_vector(g.n_vertices, 0.0, 1.0, rng));
    }
  }
}
