#include <gtest/gtest.h>

#include <cmath>

#include "strategies/convergence.h"
#include "linear_map.h"

using namespace edgedeform;
using test::LinearMap;

TEST(ConvergenceMonitor, EstimateBoundsTheTrueDistanceOfAPlainIteration) {
  const LinearMap G(30);
  ConvergenceMonitor monitor;
  monitor.resize(10);  // 30 numbers seen as 10 points in 3D
  Eigen::VectorXd x = Eigen::VectorXd::Zero(30);
  int checked = 0;
  for (int k = 0; k < 400; ++k) {
    const Eigen::VectorXd g = G(x);
    const Eigen::MatrixXd Y = Eigen::Map<const Eigen::MatrixXd>(x.data(), 10, 3);
    const Eigen::MatrixXd Gm = Eigen::Map<const Eigen::MatrixXd>(g.data(), 10, 3);
    monitor.add(Y, Gm, true);
    const double est = monitor.distance(max_row_distance(Gm, Y));
    const Eigen::VectorXd e = g - G.fixed_point;
    const double truth = max_row_distance(Eigen::Map<const Eigen::MatrixXd>(e.data(), 10, 3),
                                          Eigen::MatrixXd::Zero(10, 3));
    if (k >= 20 && std::isfinite(est)) {  // after the fast modes died out
      EXPECT_GE(est, 0.5 * truth) << "iteration " << k;
      ++checked;
    }
    x = g;
  }
  EXPECT_GT(checked, 300);
}

TEST(ConvergenceMonitor, AtTheNoiseFloorTheSlowestRateIsAssumed) {
  // Secant ratios >= 1 (noise at a residual floor): no rate. Above the noise floor nothing
  // is claimed; at it, the residual counts with the slowest contraction ever measured, so
  // a 1e-8 residual is at most ~1e-4 away, and a tight tolerance still needs a real rate.
  ConvergenceMonitor monitor;
  monitor.resize(1);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(1, 3), g = Eigen::MatrixXd::Zero(1, 3);
  for (int k = 0; k < 2 * ConvergenceMonitor::kMinRatios; ++k) {
    y(0, 0) = (k % 2 ? 1.0 : -1.0) * 1e-9;  // steps of 2e-9 ...
    g(0, 0) = (k % 2 ? -1.0 : 1.0) * 3e-9;  // ... mapped to steps of 6e-9: ratio 3
    monitor.add(y, g, true);
  }
  EXPECT_GE(monitor.rate(), 1.0);
  EXPECT_FALSE(std::isfinite(monitor.distance(1e-6)));
  const double slow = ConvergenceMonitor::kSlowestRate / (1.0 - ConvergenceMonitor::kSlowestRate);
  EXPECT_DOUBLE_EQ(monitor.distance(1e-8), 1e-8 * slow);
  EXPECT_LT(monitor.distance(ConvergenceMonitor::kNoiseFloor), 1e-3 + 1e-12);
  EXPECT_GT(monitor.distance(1e-8), 1e-8);  // never the residual alone
}

TEST(ConvergenceMonitor, NothingIsClaimedBeforeTheRateIsSeen) {
  ConvergenceMonitor monitor;
  monitor.resize(2);
  const Eigen::MatrixXd y = Eigen::MatrixXd::Zero(2, 3), g = Eigen::MatrixXd::Ones(2, 3) * 1e-3;
  monitor.add(y, g, true);
  EXPECT_FALSE(std::isfinite(monitor.distance(1e-3)));
  EXPECT_EQ(monitor.distance(1e-13), 1e-13);  // round-off: a fixed point to working precision
  monitor.add(g, g, false);                    // not a pair of the map: no ratio from it
  EXPECT_FALSE(std::isfinite(monitor.rate()));
}
