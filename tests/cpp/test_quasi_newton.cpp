// quasi_newton: L-BFGS on the energy (lambda = 1) on the constrained grid's problem: E never
// rises, a converged claim lies within the tolerance of the fixed point the plain iteration
// reaches, it takes fewer global steps than the plain iteration, two calls continue like
// one, and an interrupt throws before the next iteration.
#include <gtest/gtest.h>

#include "strategies/convergence.h"
#include "base/errors.h"
#include "strategies/fixed_point_iteration.h"
#include "strategies/quasi_newton.h"
#include "grid_problem.h"

using namespace edgedeform;
using edgedeform::test::GridProblem;

namespace {

struct ColdLbfgs {
  IterationPoint point;
  LocalFit fit;
  QuasiNewtonMemory memory;
  SolveResult result;
  explicit ColdLbfgs(GridProblem& p) : fit(test::cold_fit(p.sys)) {
    point.y = p.rest_free();
    memory.restart(p.sys.n_free());
  }
  void go(GridProblem& p, int iterations, double tolerance) {
    QuasiNewtonSettings s;
    s.max_iterations = iterations;
    s.tolerance = tolerance;
    s.diag = p.diag;
    result = SolveResult();
    quasi_newton_solve(p, s, point, fit, memory, result);
  }
};

// The plain iteration run tight: the fixed point.
Eigen::MatrixXd plain_fixed_point(GridProblem& p) {
  IterationPoint point;
  point.y = p.rest_free();
  LocalFit fit = test::cold_fit(p.sys);
  PlainAndersonMemory memory;
  memory.restart(p.sys.n_free(), 5);
  PlainAndersonSettings s;
  s.max_iterations = 20000;
  s.tolerance = 1e-12;
  s.diag = p.diag;
  s.descent = true;
  SolveResult result;
  plain_anderson_solve(p, s, point, fit, memory, result);
  EXPECT_TRUE(result.converged);
  return point.y;
}

class Lbfgs : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(Lbfgs, TheEnergyNeverRises) {
  GridProblem p(GetParam(), 1.0);
  ColdLbfgs run(p);
  run.go(p, 60, 0.0);
  const std::vector<double>& e = run.result.energies;
  ASSERT_EQ(e.size(), 60u);
  for (size_t k = 1; k < e.size(); ++k) EXPECT_LE(e[k], e[k - 1] * (1.0 + 1e-12)) << "iteration " << k;
  EXPECT_GT(run.result.accelerated_steps, 0);  // quasi-Newton steps, not only plain ones
}

TEST_P(Lbfgs, AClaimLiesWithinTheToleranceAndComesSoonerThanPlainSteps) {
  GridProblem p(GetParam(), 1.0);
  const Eigen::MatrixXd fixed = plain_fixed_point(p);
  ColdLbfgs run(p);
  const double tolerance = 1e-6;
  run.go(p, 2000, tolerance);
  ASSERT_TRUE(run.result.converged);
  EXPECT_LT(max_row_distance(run.point.y, fixed) / p.diag, 2 * tolerance);

  IterationPoint point;
  point.y = p.rest_free();
  LocalFit fit = test::cold_fit(p.sys);
  PlainAndersonMemory memory;
  memory.restart(p.sys.n_free(), 5);
  PlainAndersonSettings plain;
  plain.max_iterations = 2000;
  plain.tolerance = tolerance;
  plain.diag = p.diag;
  plain.descent = true;
  plain.accelerate = false;
  SolveResult plain_result;
  plain_anderson_solve(p, plain, point, fit, memory, plain_result);
  EXPECT_LT(run.result.iterations, plain_result.iterations);
}

TEST_P(Lbfgs, TwoCallsContinueLikeOne) {
  GridProblem p(GetParam(), 1.0);
  ColdLbfgs once(p), twice(p);
  once.go(p, 20, 0.0);
  twice.go(p, 12, 0.0);
  twice.go(p, 8, 0.0);
  EXPECT_EQ(twice.point.y, once.point.y);  // the same steps, pairs included, bit for bit
  EXPECT_EQ(twice.point.energy, once.point.energy);
}

TEST_P(Lbfgs, AnInterruptThrowsBeforeTheNextIteration) {
  GridProblem p(GetParam(), 1.0);
  ColdLbfgs run(p), three(p);
  p.interrupt_after = 3;
  EXPECT_THROW(run.go(p, 100, 0.0), SolveInterrupted);
  EXPECT_EQ(run.result.iterations, 3);
  p.interrupt_after = -1;
  three.go(p, 3, 0.0);
  EXPECT_EQ(run.point.y, three.point.y);  // the point of the last finished iteration
}

INSTANTIATE_TEST_SUITE_P(Domains, Lbfgs, ::testing::Values(Domain::Edge, Domain::Primal));
