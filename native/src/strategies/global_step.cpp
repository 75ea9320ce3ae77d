#include "strategies/global_step.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "strategies/convergence.h"

namespace edgedeform {

void start_history(SolveResult& result, int max_iterations) {
  const auto expected = static_cast<size_t>(std::min(max_iterations, 4096));
  result.energies.reserve(expected);
  result.residuals.reserve(expected);
  result.distance_estimate = std::numeric_limits<double>::infinity();
}

bool recorded_global_step(FixedPointProblem& problem, const LocalFit& fit, IterationPoint& point, double diag,
                          Eigen::MatrixXd& rhs, Eigen::MatrixXd& g, double& residual, SolveResult& result) {
  problem.global_step(fit, rhs, g);
  ++result.iterations;
  residual = max_row_distance(g, point.y) / diag;
  result.residuals.push_back(residual);
  if (std::isfinite(residual)) return true;
  result.warnings.push_back("the iteration produced non-finite positions; stopped at the last finite shape");
  result.energies.push_back(point.energy);
  point.fitted = false;
  return false;
}

}  // namespace edgedeform
