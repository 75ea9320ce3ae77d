#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>

#include "base/errors.h"
#include "base/parallel.h"
#include "linear_algebra/sparse_cholesky.h"

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

namespace {
// The 9-point Laplacian of a side x side grid plus `shift`: its factor has supernodes of
// several columns with rows below them (the 1-D one above has only single columns).
SparseMatrix grid(int side, double shift) {
  std::vector<Eigen::Triplet<double>> t;
  const auto id = [side](int x, int y) { return y * side + x; };
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      double degree = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || x + dx < 0 || y + dy < 0 || x + dx >= side || y + dy >= side) continue;
          const double w = (dx == 0 || dy == 0) ? 1.0 : 0.5;
          t.emplace_back(id(x, y), id(x + dx, y + dy), -w);
          degree += w;
        }
      t.emplace_back(id(x, y), id(x, y), degree + shift);
    }
  SparseMatrix A(side * side, side * side);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}
}  // namespace

TEST(SparseCholesky, SolvesAGridLikeADenseCholesky) {
  const SparseMatrix A = grid(30, 0.01);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(A);
  const Eigen::LLT<Eigen::MatrixXd> reference(dense);
  SparseCholesky chol;
  chol.factorize(A);
  for (int k : {1, 3, 5}) {
    const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), k);
    Eigen::MatrixXd X;
    chol.solve(B, X);
    const Eigen::MatrixXd expected = reference.solve(B);
    ASSERT_EQ(X.rows(), A.rows());
    ASSERT_EQ(X.cols(), k);
    EXPECT_LT((X - expected).norm() / expected.norm(), 1e-12) << k << " columns";
    EXPECT_LT((dense * X - B).norm() / B.norm(), 1e-12) << k << " columns";
  }
  // New values in the same pattern: the solve reads the new factor.
  chol.factorize(grid(30, 2.0));
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
  Eigen::MatrixXd X;
  chol.solve(B, X);
  EXPECT_LT((Eigen::MatrixXd(grid(30, 2.0)) * X - B).norm() / B.norm(), 1e-12);
}

TEST(SparseCholesky, RefusesRightHandSidesOfTheWrongShape) {
  SparseCholesky chol;
  chol.factorize(grid(10, 0.1));
  Eigen::MatrixXd X = Eigen::MatrixXd::Constant(2, 2, 7.0);
  EXPECT_THROW(chol.solve(Eigen::MatrixXd::Ones(99, 3), X), std::invalid_argument);
  EXPECT_THROW(chol.solve(Eigen::MatrixXd::Ones(100, 0), X), std::invalid_argument);
  EXPECT_THROW(chol.solve(Eigen::MatrixXd::Ones(100, 17), X), std::invalid_argument);
  EXPECT_EQ(X, Eigen::MatrixXd::Constant(2, 2, 7.0));  // untouched
  chol.solve(Eigen::MatrixXd::Ones(100, 3), X);        // and still usable
  EXPECT_EQ(X.rows(), 100);
}

TEST(SparseCholesky, SolvesALargeGridOnTwoThreadsDeterministically) {
  // 10,000 unknowns: a factor large enough to split (supernodal_solve.h) on two threads.
  const SparseMatrix A = grid(100, 0.001);
  SparseCholesky chol;
  chol.factorize(A);
  // The Eigen fallback (SimplicialLDLT) solves on one thread.
  const bool supernodal = std::string(SparseCholesky::backend()) == "cholmod-supernodal";
  // Split whatever the thread count: one thread runs the halves in turn with the same sums.
  EXPECT_EQ(chol.solves_in_parallel(), supernodal);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(A.rows(), 3);
  Eigen::MatrixXd X;
  chol.solve(B, X);
  Eigen::SimplicialLLT<SparseMatrix> reference(A);
  const Eigen::MatrixXd expected = reference.solve(B);
  EXPECT_LT((X - expected).norm() / expected.norm(), 1e-11);
  EXPECT_LT((A * X - B).norm() / B.norm(), 1e-12);
  // Whichever thread runs which half, the sums are formed in one order: the same bits.
  for (int repeat = 0; repeat < 20; ++repeat) {
    Eigen::MatrixXd again;
    chol.solve(B, again);
    ASSERT_EQ(again, X) << "repeat " << repeat;
  }
}
