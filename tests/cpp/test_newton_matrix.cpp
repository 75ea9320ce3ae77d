// newton_matrix: the assembled K equals the matrix-free Newton operator
// (FixedPointLinearization::newton_operator) on every column, in both domains, at lambda
// 1, 0.5 and 0, with and without the positive model; it is symmetric at lambda = 1, and
// positive definite there with the positive model. (Thread counts: the solver's positions
// are compared across 1, 2 and 4 threads in tests/python/test_newton.py.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <tuple>

#include <Eigen/Dense>

#include "constrained_grid.h"
#include "edgedeform/fixed_point_linearization.h"
#include "edgedeform/newton_matrix.h"

using namespace edgedeform;

namespace {

// The grid's whole set at one lambda, linearized at a bent and stretched shape.
struct Linearized {
  test::ConstrainedGrid grid;
  ConstrainedSystem sys;
  AssembledSystem as;
  RowMatrixX3d nodes;
  LocalFit fit;
  Linearized(Domain domain, double lambda) : grid(domain) {
    sys = grid.whole(grid.whole_sets);
    as = assemble_system(sys, Eigen::VectorXd::Constant(grid.g.n_vertices, lambda));
    RowMatrixX3d x_local(sys.n_free() + sys.n_fixed(), 3);
    for (int k = 0; k < sys.n_free() + sys.n_fixed(); ++k) {
      const int v = k < sys.n_free() ? sys.free_vertices[static_cast<size_t>(k)]
                                     : sys.fixed_vertices[static_cast<size_t>(k - sys.n_free())];
      const Eigen::RowVector3d p = grid.mesh.V.row(v);
      x_local.row(k) << 1.2 * p(0) + 0.15 * p(1) * p(1), 0.9 * p(1) + 0.1 * std::sin(3 * p(0)), p(2) + 0.3 * p(0) * p(1);
    }
    stencil_node_positions(sys, x_local, nodes);
    fit_local(sys.stencil, nodes, as.term_lambda, fit, as.term_similar);
  }
};

// dx (nf x 3, column-major like the strategies') as K's interleaved vector, and back.
Eigen::VectorXd interleave(const Eigen::MatrixXd& dx) {
  Eigen::VectorXd v(dx.size());
  for (Eigen::Index r = 0; r < dx.rows(); ++r)
    for (int c = 0; c < 3; ++c) v(3 * r + c) = dx(r, c);
  return v;
}

// K itself (NewtonMatrix stores its transpose).
SparseMatrix K_of(const NewtonMatrix& K) { return SparseMatrix(K.transpose().transpose()); }

class NewtonMatrixCase : public ::testing::TestWithParam<std::tuple<Domain, double, bool>> {};

}  // namespace

TEST_P(NewtonMatrixCase, EqualsTheMatrixFreeOperator) {
  const auto [domain, lambda, positive_model] = GetParam();
  Linearized s(domain, lambda);
  const FixedPointLinearization lin(s.sys, s.as, s.fit, s.nodes, positive_model);
  NewtonMatrix K(s.sys, s.as);
  K.assemble(lin);
  const int nf = s.sys.n_free();
  ASSERT_EQ(K_of(K).rows(), 3 * nf);
  std::srand(11);
  const Eigen::MatrixXd dx = Eigen::MatrixXd::Random(nf, 3);
  Eigen::MatrixXd expected;
  lin.newton_operator(dx, expected);
  const Eigen::VectorXd got = K_of(K) * interleave(dx);
  const Eigen::VectorXd want = interleave(expected);
  ASSERT_GT(want.norm(), 1e-3);
  EXPECT_LE((got - want).norm(), 1e-12 * want.norm());
  // Every column, not only a random combination of them: unit vectors.
  for (int col : {0, 1, 2, 3 * nf / 2, 3 * nf - 1}) {
    Eigen::MatrixXd e = Eigen::MatrixXd::Zero(nf, 3);
    e(col / 3, col % 3) = 1.0;
    lin.newton_operator(e, expected);
    EXPECT_LE((Eigen::VectorXd(K_of(K).col(col)) - interleave(expected)).norm(), 1e-12 * (1.0 + expected.norm()))
        << "column " << col;
  }
  const SparseMatrix asymmetry = SparseMatrix(K_of(K).transpose()) - K_of(K);
  const double size = K_of(K).norm();
  if (lambda == 1.0) {
    EXPECT_LE(asymmetry.norm(), 1e-12 * size);
  } else {
    EXPECT_GT(asymmetry.norm(), 1e-6 * size);  // the fixed-point map of lambda < 1 is no gradient
  }
  if (positive_model) {
    const Eigen::MatrixXd dense(K_of(K));
    const Eigen::VectorXd eig = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(0.5 * (dense + dense.transpose())).eigenvalues();
    EXPECT_GT(eig.minCoeff(), 0.0);
  }
}

TEST(NewtonMatrix, TheBlockPatternHoldsEveryEntryAndOrdersExpandPerCoordinate) {
  Linearized s(Domain::Edge, 1.0);  // at lambda < 1 A's Laplacian part couples the diamond already
  const FixedPointLinearization lin(s.sys, s.as, s.fit, s.nodes);
  NewtonMatrix K(s.sys, s.as);
  K.assemble(lin);
  const SparseMatrix P = K.block_pattern();
  ASSERT_EQ(P.rows(), s.sys.n_free());
  const SparseMatrix whole = K_of(K);
  for (int j = 0; j < whole.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(whole, j); it; ++it)
      EXPECT_NE(P.coeff(it.row() / 3, j / 3), 0.0);
  // Symmetric pattern (the factorization analyses one triangle).
  EXPECT_EQ((SparseMatrix(P.transpose()) - P).norm(), 0.0);
  // The diamond's opposite vertices couple: more blocks than A has.
  EXPECT_GT(P.nonZeros(), s.as.A.nonZeros());
  EXPECT_EQ(NewtonMatrix::coordinate_order({2, 0}), (std::vector<int>{6, 7, 8, 0, 1, 2}));
}

TEST(NewtonMatrix, RefusesAnotherSystemsLinearization) {
  Linearized a(Domain::Edge, 0.5), b(Domain::Edge, 0.5);
  const FixedPointLinearization lin(b.sys, b.as, b.fit, b.nodes);
  NewtonMatrix K(a.sys, a.as);
  EXPECT_THROW(K.assemble(lin), std::logic_error);
}

INSTANTIATE_TEST_SUITE_P(DomainsLambdas, NewtonMatrixCase,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal),
                                            ::testing::Values(1.0, 0.5, 0.0), ::testing::Values(false)));
// The per-node positive model is for lambda = 1 only.
INSTANTIATE_TEST_SUITE_P(PositiveModel, NewtonMatrixCase,
                         ::testing::Combine(::testing::Values(Domain::Edge, Domain::Primal), ::testing::Values(1.0),
                                            ::testing::Values(true)));
