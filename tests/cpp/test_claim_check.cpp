// claim_check: Arnoldi's largest Ritz modulus finds a slow mode that a residual hides.
#include <gtest/gtest.h>

#include "strategies/claim_check.h"
#include "strategies/convergence.h"

using namespace edgedeform;

namespace {

// A diagonal map on 100 x 3 numbers: one slow mode (0.9996), the rest at most 0.9.
struct SlowMode {
  Eigen::MatrixXd diag = Eigen::MatrixXd::Zero(100, 3);
  SlowMode() {
    for (int r = 0; r < 100; ++r)
      for (int c = 0; c < 3; ++c) diag(r, c) = 0.9 * (r * 3 + c) / 300.0;
    diag(37, 1) = 0.9996;
  }
  void operator()(const Eigen::MatrixXd& in, Eigen::MatrixXd& out) const { out = diag.cwiseProduct(in); }
};

}  // namespace

TEST(ClaimCheck, ArnoldiFindsTheSlowModeUnderAFastResidual) {
  const SlowMode map;
  // The residual is mostly fast modes; the slow mode's share is 1e-4 of it.
  Eigen::MatrixXd residual = Eigen::MatrixXd::Constant(100, 3, 1.0);
  residual(37, 1) = 1e-4;
  const double rho = largest_ritz_modulus(std::cref(map), residual, kClaimCheckSteps);
  EXPECT_GT(rho, 0.999);
  EXPECT_LE(rho, 0.9996 + 1e-12);  // a Ritz value never exceeds the largest modulus here
}

TEST(ClaimCheck, ZeroStartAndInvariantSubspacesAreHandled) {
  const SlowMode map;
  EXPECT_EQ(largest_ritz_modulus(std::cref(map), Eigen::MatrixXd::Zero(100, 3), 10), 0.0);
  Eigen::MatrixXd only_slow = Eigen::MatrixXd::Zero(100, 3);
  only_slow(37, 1) = 2.0;  // an eigenvector: one step spans an invariant subspace
  EXPECT_NEAR(largest_ritz_modulus(std::cref(map), only_slow, 10), 0.9996, 1e-12);
}

TEST(ConvergenceMonitor, ARaisedRateHoldsUntilTheNextReset) {
  ConvergenceMonitor monitor;
  monitor.resize(1);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(1, 3), g = y;
  for (int k = 0; k <= ConvergenceMonitor::kMinRatios; ++k) {  // ratios of 0.5
    y(0, 0) = std::pow(0.5, k);
    g(0, 0) = std::pow(0.5, k + 1);
    monitor.add(y, g, true);
  }
  EXPECT_DOUBLE_EQ(monitor.rate(), 0.5);
  monitor.raise_rate(0.999);
  EXPECT_DOUBLE_EQ(monitor.rate(), 0.999);
  EXPECT_NEAR(monitor.distance(1e-6), 1e-6 * 0.999 / 0.001, 1e-12);
  monitor.raise_rate(0.9);  // never lowered
  EXPECT_DOUBLE_EQ(monitor.rate(), 0.999);
  monitor.reset();
  EXPECT_FALSE(std::isfinite(monitor.rate()));
}
