// The half of an iteration every strategy shares: the global step from the current fit and
// its residual, recorded in the result; and the result's room for its per-iteration history.
#pragma once

#include <Eigen/Core>

#include "strategies/fixed_point_problem.h"
#include "base/iteration_point.h"
#include "base/solve_types.h"

namespace edgedeform {

// Reserves the usual solve's energies and residuals, not max_iterations' (which may be
// 2^31 - 1: 16 GiB each), and starts with no distance estimate.
void start_history(SolveResult& result, int max_iterations);

// g := G(y) for point's fit (rhs is scratch); counts the iteration and records the
// residual |g - y|_max / diag in `residual` and the result. Returns false, with a warning
// and the point's energy recorded, when the step is not finite: y stays the last finite
// iterate and the caller returns.
bool recorded_global_step(FixedPointProblem& problem, const LocalFit& fit, IterationPoint& point, double diag,
                          Eigen::MatrixXd& rhs, Eigen::MatrixXd& g, double& residual, SolveResult& result);

}  // namespace edgedeform
