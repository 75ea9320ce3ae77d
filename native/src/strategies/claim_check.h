// A second opinion on a convergence claim (docs/decisions/0025): the secant-rate estimate
// can miss a slow mode that dominates the error but not the residual (the 50k koala's Live
// settle claimed 9.4e-4 while 4.7e-3 away). At the claimed point, k Arnoldi steps on J_G
// started from the residual give the largest Ritz value's modulus rho, and the bound
// r rho / (1 - rho) on the plain step's distance to the fixed point.
#pragma once

#include <functional>

#include <Eigen/Core>

#include "strategies/convergence.h"
#include "strategies/fixed_point_problem.h"
#include "base/solve_types.h"

namespace edgedeform {

// Arnoldi steps per check: k = 20 refused the koala's false claim and kept the cold
// solve's true one (record 0025); 40 came closer to the slowest modulus at twice the cost.
constexpr int kClaimCheckSteps = 30;

// The largest Ritz value's modulus of `steps` Arnoldi steps on the map `apply` (out = M in,
// #free x 3 blocks), started from `start`. 0 when start is zero.
double largest_ritz_modulus(const std::function<void(const Eigen::MatrixXd&, Eigen::MatrixXd&)>& apply,
                            const Eigen::MatrixXd& start, int steps);

// What every strategy asks after its global step g = G(y) (residual r = |g - y| / diag):
// the estimated distance of g to the fixed point, infinite unless (y, g) is a map pair (fit
// = fit(y)). With `verify_claims`, an estimate below `tolerance` is checked first (the rate
// raised to the modulus of kClaimCheckSteps Arnoldi steps on J_G at y, started
// from g - y; result.claim_checks, refused_claims counted).
double checked_distance(FixedPointProblem& problem, ConvergenceMonitor& monitor, const LocalFit& fit,
                        const Eigen::MatrixXd& y, const Eigen::MatrixXd& g, double r, bool map_pair,
                        bool verify_claims, double tolerance, SolveResult& result);

}  // namespace edgedeform
