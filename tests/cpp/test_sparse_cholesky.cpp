#include <gtest/gtest.h>

#include "edgedeform/errors.h"
#include "edgedeform/sparse_cholesky.h"

using namespace edgedeform;

namespace {
// 1-D Laplacian plus `shift` on the diagonal: SPD for shift > 0.
SparseMatrix tridiagonal(int n, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2.0 + shift);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}
}  // namespace

TEST(SparseCholesky, SolvesThreeColumns) {
  SparseCholesky chol;
  const SparseMatrix A = tridiagonal(200, 0.1);
  chol.factorize(A);
  const Eigen::MatrixXd X = Eigen::MatrixXd::Random(200, 3);
  Eigen::MatrixXd Y;
  chol.solve(A * X, Y);
  EXPECT_LT((Y - X).norm() / X.norm(), 1e-12);
}

TEST(SparseCholesky, KeepsTheAnalysisWhileThePatternStays) {
  SparseCholesky chol;
  chol.factorize(tridiagonal(100, 0.1));
  chol.factorize(tridiagonal(100, 5.0));  // new values, same pattern
  EXPECT_EQ(chol.analyses(), 1);
  chol.factorize(tridiagonal(101, 0.1));
  EXPECT_EQ(chol.analyses(), 2);
  const SparseMatrix A = tridiagonal(101, 0.1);
  Eigen::MatrixXd Y;
  chol.solve(A * Eigen::MatrixXd::Ones(101, 3), Y);
  EXPECT_LT((Y.array() - 1.0).abs().maxCoeff(), 1e-10);
}

TEST(SparseCholesky, NotPositiveDefiniteIsAClearError) {
  SparseCholesky chol;
  EXPECT_THROW(chol.factorize(tridiagonal(50, -3.0)), FactorizationError);
  EXPECT_FALSE(chol.factored());
  Eigen::MatrixXd Y;
  EXPECT_THROW(chol.solve(Eigen::MatrixXd::Ones(50, 3), Y), FactorizationError);
  chol.factorize(tridiagonal(50, 1.0));  // usable again afterwards
  EXPECT_TRUE(chol.factored());
}

TEST(SparseCholesky, ReportsItsBackend) {
  const std::string backend = SparseCholesky::backend();
  EXPECT_TRUE(backend == "cholmod-supernodal" || backend == "eigen-simplicial-ldlt");
}
