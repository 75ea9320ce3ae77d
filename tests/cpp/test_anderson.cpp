#include <gtest/gtest.h>

#include "strategies/anderson.h"
#include "linear_map.h"

using namespace edgedeform;
using test::LinearMap;

namespace {

int iterations_to(const LinearMap& G, bool accelerate, double tol, Eigen::VectorXd* result = nullptr) {
  const auto n = G.b.size();
  AndersonAccelerator aa;
  aa.resize(n, 5);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), next(n);
  for (int k = 1; k <= 5000; ++k) {
    const Eigen::VectorXd g = G(x);
    if ((g - x).norm() < tol) {
      if (result) *result = g;
      return k;
    }
    if (accelerate)
      aa.step(x, g, next);
    else
      next = g;
    x = next;
  }
  return -1;
}

}  // namespace

TEST(Anderson, ReachesTheSameFixedPointInFarFewerIterations) {
  const LinearMap G(40);
  Eigen::VectorXd plain_x, fast_x;
  const int plain = iterations_to(G, false, 1e-10, &plain_x);
  const int fast = iterations_to(G, true, 1e-10, &fast_x);
  ASSERT_GT(plain, 0);
  ASSERT_GT(fast, 0);
  EXPECT_LT(3 * fast, plain);
  EXPECT_LT((fast_x - G.fixed_point).norm(), 1e-8);
  EXPECT_LT((plain_x - G.fixed_point).norm(), 1e-8);
}

TEST(Anderson, FirstStepAndStepAfterResetArePlain) {
  const LinearMap G(10);
  AndersonAccelerator aa;
  aa.resize(10, 5);
  Eigen::VectorXd x = Eigen::VectorXd::Ones(10), out(10);
  EXPECT_FALSE(aa.step(x, G(x), out));
  EXPECT_EQ(out, G(x));
  const Eigen::VectorXd x2 = out;
  EXPECT_TRUE(aa.step(x2, G(x2), out));
  aa.reset();
  EXPECT_EQ(aa.stored(), 0);
  EXPECT_FALSE(aa.step(out, G(out), x));
}

TEST(Anderson, AResetForgetsOldColumns) {
  // The same pairs after a reset give the same point as a fresh accelerator.
  const LinearMap G(12);
  AndersonAccelerator used, fresh;
  used.resize(12, 3);
  fresh.resize(12, 3);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(12), out(12);
  for (int k = 0; k < 7; ++k) {  // wrap the ring buffer
    used.step(x, G(x), out);
    x = out;
  }
  used.reset();
  Eigen::VectorXd y = Eigen::VectorXd::Ones(12), a(12), b(12);
  for (int k = 0; k < 3; ++k) {
    used.step(y, G(y), a);
    fresh.step(y, G(y), b);
    ASSERT_EQ(a, b);
    y = a;
  }
}
