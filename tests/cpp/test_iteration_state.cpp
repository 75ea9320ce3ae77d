// IterationState: which transitions let a warm solve continue the iteration, and what a
// restart keeps (the last positions when asked and still the free vertices', else rest).
#include <gtest/gtest.h>

#include "strategies/iteration_state.h"

using namespace edgedeform;

namespace {

RowMatrixX3d rows(int n, double value) { return RowMatrixX3d::Constant(n, 3, value); }

// A state that has just finished a solve towards `targets` with y = 7 everywhere, fitted.
IterationState finished_at(const RowMatrixX3d& targets, const std::vector<int>& free_vertices) {
  IterationState state;
  state.restart(targets, rows(4, 0.0), free_vertices, true, 5);
  state.point.y.setConstant(7.0);
  state.point.fitted = true;
  state.finished();
  return state;
}

}  // namespace

TEST(IterationState, AFinishedSolveIsContinuedOnlyTowardsTheSameTargets) {
  const RowMatrixX3d targets = rows(1, 1.0);
  const IterationState state = finished_at(targets, {0, 2});
  EXPECT_TRUE(state.continues(targets));
  EXPECT_FALSE(state.continues(rows(1, 2.0)));
  EXPECT_FALSE(state.continues(rows(2, 1.0)));
}

TEST(IterationState, ANewSystemOrAnInterruptEndsTheIteration) {
  const RowMatrixX3d targets = rows(1, 1.0);
  IterationState changed = finished_at(targets, {0, 2}), interrupted = finished_at(targets, {0, 2});
  changed.system_changed();
  interrupted.interrupted();
  EXPECT_FALSE(changed.continues(targets));
  EXPECT_FALSE(interrupted.continues(targets));
}

TEST(IterationState, ARestartKeepsTheLastPositionsOnlyWhenAskedAndStillValid) {
  RowMatrixX3d rest(4, 3);
  rest << 0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3;
  const std::vector<int> free_vertices = {0, 2};
  IterationState kept = finished_at(rows(1, 1.0), free_vertices);
  kept.restart(rows(1, 2.0), rest, free_vertices, true, 5);
  EXPECT_EQ(kept.point.y, Eigen::MatrixXd::Constant(2, 3, 7.0));  // a warm restart moves on from there
  EXPECT_FALSE(kept.point.fitted);

  IterationState cold = finished_at(rows(1, 1.0), free_vertices);
  cold.restart(rows(1, 2.0), rest, free_vertices, false, 5);
  EXPECT_EQ(cold.point.y.row(1), rest.row(2));

  IterationState moved = finished_at(rows(1, 1.0), free_vertices);
  moved.free_set_changed();  // same count of free vertices, but not the same ones
  moved.restart(rows(1, 2.0), rest, free_vertices, true, 5);
  EXPECT_EQ(moved.point.y.row(0), rest.row(0));
  EXPECT_EQ(moved.point.y.row(1), rest.row(2));
}

TEST(IterationState, ARestartResetsTheStrategiesState) {
  IterationState state = finished_at(rows(1, 1.0), {0, 2});
  state.last_method = Acceleration::Lbfgs;
  state.restart(rows(1, 2.0), rows(4, 0.0), {0, 2}, true, 5);
  EXPECT_EQ(state.last_method, Acceleration::Automatic);  // no strategy has moved the new iteration
  EXPECT_FALSE(state.point.fitted);
}
