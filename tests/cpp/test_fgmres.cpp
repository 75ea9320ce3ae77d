#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "edgedeform/fgmres.h"

using namespace edgedeform;

namespace {

LinearMap dense(const Eigen::MatrixXd& M) {
  return [M](const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = M * in; };
}

Eigen::MatrixXd spd(int n) {
  std::srand(7);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, n);
  return B * B.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

}  // namespace

TEST(Fgmres, SolvesAnSpdSystemToItsTolerance) {
  const Eigen::MatrixXd M = spd(40);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(40, -1.0, 2.0);
  Eigen::VectorXd x;
  const KrylovResult r = fgmres(dense(M), {}, b, x, 1e-8, 40);
  ASSERT_TRUE(r.converged);
  EXPECT_LE((b - M * x).norm(), 1e-8 * b.norm() * 1.0001);
  EXPECT_NEAR(r.relative_residual, (b - M * x).norm() / b.norm(), 1e-10);
}

TEST(Fgmres, SolvesANonSymmetricSystemWithAPreconditioner) {
  std::srand(11);
  const int n = 60;
  const Eigen::MatrixXd M = Eigen::MatrixXd::Identity(n, n) * 4.0 + Eigen::MatrixXd::Random(n, n);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(n);
  const Eigen::MatrixXd diagonal_inverse = M.diagonal().cwiseInverse().asDiagonal();
  Eigen::VectorXd x;
  const KrylovResult r = fgmres(dense(M), dense(diagonal_inverse), b, x, 1e-10, 60);
  ASSERT_TRUE(r.converged);
  EXPECT_LE((b - M * x).norm(), 1.0001e-10 * b.norm());
  // An exact preconditioner solves in one product.
  Eigen::VectorXd y;
  const KrylovResult exact = fgmres(dense(M), dense(M.inverse()), b, y, 1e-10, 60);
  EXPECT_EQ(exact.iterations, 1);
  EXPECT_LE((b - M * y).norm(), 1e-9 * b.norm());
}

TEST(Fgmres, StopsAtItsIterationLimitWithTheResidualItReached) {
  const Eigen::MatrixXd M = spd(50);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(50);
  Eigen::VectorXd x;
  const KrylovResult r = fgmres(dense(M), {}, b, x, 1e-14, 3);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_FALSE(r.converged);
  EXPECT_NEAR(r.relative_residual, (b - M * x).norm() / b.norm(), 1e-10);
  EXPECT_LT(r.relative_residual, 1.0);
}

TEST(Fgmres, AZeroRightSideGivesZeroAndAStopRequestEndsAtOnce) {
  const Eigen::MatrixXd M = spd(10);
  Eigen::VectorXd x;
  EXPECT_TRUE(fgmres(dense(M), {}, Eigen::VectorXd::Zero(10), x, 1e-8, 10).converged);
  EXPECT_EQ(x.norm(), 0.0);
  const KrylovResult stopped = fgmres(dense(M), {}, Eigen::VectorXd::Ones(10), x, 1e-8, 10, [] { return true; });
  EXPECT_EQ(stopped.iterations, 0);
  EXPECT_EQ(x.norm(), 0.0);
}
