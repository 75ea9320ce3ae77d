#include "strategies/fixed_point_iteration.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "strategies/claim_check.h"
#include "strategies/global_step.h"
#include "base/errors.h"

namespace edgedeform {

namespace {
// An accelerated point (lambda < 1) is kept while its residual stays below this multiple of
// the best residual so far (see plain_anderson_solve).
constexpr double kResidualSlack = 2.0;
}  // namespace

void PlainAndersonMemory::restart(int nf, int window) {
  g.resize(nf, 3);
  next.resize(nf, 3);
  base_step.resize(nf, 3);
  anderson.resize(3 * static_cast<Eigen::Index>(nf), window);
  monitor.resize(nf);
  y_accelerated = false;
  best_residual = std::numeric_limits<double>::infinity();
}

// The fixed-point iteration x -> G(x) = global(local(x)). y is the current point, with fit =
// its local step unless point.fitted is false, as on the first step of a cold start; the
// Anderson history lives in the memory.
//
// Each iteration takes one global step from y, g = G(y), and measures r = |g - y| / diag.
// - If the estimated distance of g to the fixed point is below the tolerance, g is the
//   result: the plain step is what the estimate bounds (convergence.h).
// - Anderson safeguard (Peng et al. 2018 §3.2). With lambda = 1 on every term the iteration
//   is block descent on E: an accelerated point is kept only if E does not rise above E(y),
//   else the plain step g is taken (E(g) <= E(y)), so energies stay monotone. With some
//   lambda < 1 the plain scheme is not a descent method, so E says nothing; instead an
//   accelerated point is judged by its own residual, known after its global step: it is kept
//   only if that residual is below kResidualSlack times the smallest residual seen since the
//   targets were set, else the iteration returns to the plain step it replaced and the
//   history restarts. Kept points therefore never stray further from the fixed point (in
//   residual) than a constant times the best point so far, which bounds the accelerated
//   iteration wherever the plain one contracts; a strict decrease (slack 1) was measured to
//   reject most useful steps, since Anderson residuals are not monotone (dino lift, lambda
//   0.5: 323 of 332 steps rejected, more iterations than plain). Both safeguards only choose
//   between points; the fixed points are those of G.
void plain_anderson_solve(FixedPointProblem& problem, const PlainAndersonSettings& settings, IterationPoint& point,
                          LocalFit& fit, PlainAndersonMemory& m, SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  const bool accelerate = settings.accelerate;
  const bool descent = settings.descent;
  const Eigen::Index dim = y.size();
  start_history(result, settings.max_iterations);

  for (int k = 0; k < settings.max_iterations; ++k) {
    if (problem.interrupt_requested()) throw SolveInterrupted("solve interrupted");
    double r = 0.0;
    if (!recorded_global_step(problem, fit, point, settings.diag, m.rhs, m.g, r, result)) return;
    const bool map_pair = point.fitted;  // g = G(y)
    result.distance_estimate = checked_distance(problem, m.monitor, fit, y, m.g, r, map_pair,
                                                settings.verify_claims, settings.tolerance, result);
    if (result.distance_estimate < settings.tolerance) {  // done: the result is the plain step
      y.swap(m.g);
      point.energy = problem.local_fit(y, fit);
      result.energies.push_back(fit.energy);
      m.y_accelerated = false;
      point.fitted = true;
      result.converged = true;
      return;
    }

    if (accelerate && !descent && m.y_accelerated && !(r < kResidualSlack * m.best_residual)) {
      // The accelerated point's residual is not below kResidualSlack times the best: back to
      // the plain step it replaced.
      ++result.rejected_steps;
      m.anderson.reset();
      y = m.base_step;
      m.y_accelerated = false;
      point.energy = problem.local_fit(y, fit);
      result.energies.push_back(fit.energy);
      continue;
    }
    if (map_pair) m.best_residual = std::min(m.best_residual, r);
    if (accelerate && !descent) m.base_step = m.g;  // the fallback if the next point fails

    bool extrapolated = false;
    if (accelerate && map_pair) {
      Eigen::Map<const Eigen::VectorXd> yv(y.data(), dim), gv(m.g.data(), dim);
      Eigen::Map<Eigen::VectorXd> next(m.next.data(), dim);
      extrapolated = m.anderson.step(yv, gv, next);
    }
    if (extrapolated) {
      problem.local_fit(m.next, fit);
      if (!std::isfinite(fit.energy) || (descent && fit.energy > point.energy)) {  // E rose: plain step, fresh history
        ++result.rejected_steps;
        m.anderson.reset();
        extrapolated = false;
      } else {
        ++result.accelerated_steps;
        y.swap(m.next);
      }
    }
    if (!extrapolated) {
      y.swap(m.g);
      problem.local_fit(y, fit);
    }
    m.y_accelerated = extrapolated;
    point.energy = fit.energy;
    point.fitted = true;
    result.energies.push_back(fit.energy);
  }
  result.warnings.push_back(not_converged_warning(settings.max_iterations, result.distance_estimate, settings.tolerance,
                                                  "the estimated distance to the fixed point is",
                                                  "the iteration has not been seen to contract"));
}

}  // namespace edgedeform
