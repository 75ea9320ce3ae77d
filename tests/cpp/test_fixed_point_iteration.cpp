// fixed_point_iteration: the plain and Anderson strategies on a FixedPointProblem built from
// the core's pieces (a lifted grid): the plain energy is monotone at lambda = 1, Anderson
// keeps it monotone there, a converged claim lies within the tolerance of the fixed point,
// two calls continue like one, and an interrupt throws before the next iteration (the
// Deformer marks its iteration unfitted: test_iteration_state.cpp).
#include <gtest/gtest.h>

#include <memory>

#include "strategies/convergence.h"
#include "base/errors.h"
#include "strategies/fixed_point_iteration.h"
#include "grid_problem.h"

using namespace edgedeform;
using edgedeform::test::GridProblem;

namespace {

// A cold run: y at rest, R = I, s = 1 (not a fit of y).
struct ColdRun {
  IterationPoint point;
  LocalFit fit;
  PlainAndersonMemory memory;
  SolveResult result;
  ColdRun(GridProblem& p, int window) : fit(test::cold_fit(p.sys)) {
    point.y = p.rest_free();
    memory.restart(p.sys.n_free(), window);
  }
  void go(GridProblem& p, const PlainAndersonSettings& s) {
    result = SolveResult();
    plain_anderson_solve(p, s, point, fit, memory, result);
  }
};

PlainAndersonSettings settings(const GridProblem& p, int iterations, double tolerance, bool accelerate) {
  PlainAndersonSettings s;
  s.max_iterations = iterations;
  s.tolerance = tolerance;
  s.diag = p.diag;
  s.descent = p.as.term_lambda.minCoeff() >= 1.0;
  s.accelerate = accelerate;
  return s;
}

void expect_monotone(const std::vector<double>& e) {
  ASSERT_GT(e.size(), 2u);
  for (size_t k = 1; k < e.size(); ++k) EXPECT_LE(e[k], e[k - 1] * (1.0 + 1e-12)) << "iteration " << k;
  EXPECT_LT(e.back(), e.front());  // it did descend
}

class Strategies : public ::testing::TestWithParam<Domain> {};

}  // namespace

TEST_P(Strategies, PlainEnergyIsMonotoneAtLambda1) {
  GridProblem p(GetParam(), 1.0);
  ColdRun run(p, 5);
  run.go(p, settings(p, 40, 0.0, false));
  EXPECT_EQ(run.result.iterations, 40);
  EXPECT_EQ(run.result.accelerated_steps, 0);
  expect_monotone(run.result.energies);
  EXPECT_FALSE(run.result.converged);
  ASSERT_FALSE(run.result.warnings.empty());  // says why it stopped
}

TEST_P(Strategies, AndersonKeepsTheEnergyMonotoneAtLambda1AndConvergesSooner) {
  // Window 3 on this edit extrapolates uphill now and then: without the energy safeguard
  // E rose 9 times (edge) and 2 times (primal) on the way.
  GridProblem p(GetParam(), 1.0);
  ColdRun anderson(p, 3), plain(p, 3);
  anderson.go(p, settings(p, 2000, 1e-6, true));
  plain.go(p, settings(p, 2000, 1e-6, false));
  ASSERT_TRUE(anderson.result.converged);
  EXPECT_GT(anderson.result.accelerated_steps, 0);
  EXPECT_GT(anderson.result.rejected_steps, 0);  // the safeguard was needed
  expect_monotone(anderson.result.energies);
  EXPECT_LT(anderson.result.iterations, plain.result.iterations);
}

TEST_P(Strategies, AConvergedClaimLiesWithinTheToleranceOfTheFixedPoint) {
  for (const double lambda : {0.5, 1.0}) {
    GridProblem p(GetParam(), lambda);
    ColdRun reference(p, 5), run(p, 5);
    reference.go(p, settings(p, 5000, 1e-12, true));
    ASSERT_TRUE(reference.result.converged);
    const double tolerance = 1e-3;
    run.go(p, settings(p, 2000, tolerance, true));
    ASSERT_TRUE(run.result.converged);
    EXPECT_LT(max_row_distance(run.point.y, reference.point.y) / p.diag, tolerance) << "lambda " << lambda;
    EXPECT_GT(run.result.iterations, 1);
  }
}

TEST_P(Strategies, TwoCallsContinueLikeOne) {
  GridProblem p(GetParam(), 0.5);
  ColdRun once(p, 5), twice(p, 5);
  once.go(p, settings(p, 20, 0.0, false));
  twice.go(p, settings(p, 12, 0.0, false));
  ASSERT_TRUE(twice.point.fitted);
  twice.go(p, settings(p, 8, 0.0, false));
  EXPECT_EQ(twice.point.y, once.point.y);  // the same plain steps, bit for bit
  EXPECT_EQ(twice.point.energy, once.point.energy);
}

TEST_P(Strategies, AnInterruptThrowsBeforeTheNextIteration) {
  GridProblem p(GetParam(), 0.5);
  ColdRun run(p, 5);
  p.interrupt_after = 3;
  EXPECT_THROW(run.go(p, settings(p, 100, 0.0, true)), SolveInterrupted);
  EXPECT_EQ(run.result.iterations, 3);
  p.interrupt_after = -1;
  ColdRun three(p, 5);
  three.go(p, settings(p, 3, 0.0, true));
  EXPECT_EQ(run.point.y, three.point.y);  // the point of the last finished iteration
}

INSTANTIATE_TEST_SUITE_P(Domains, Strategies, ::testing::Values(Domain::Edge, Domain::Primal));
