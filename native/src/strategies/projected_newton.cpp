#include "edgedeform/projected_newton.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "edgedeform/convergence.h"
#include "edgedeform/errors.h"

namespace edgedeform {

namespace {

constexpr double kArmijo = 1e-4;
constexpr int kBacktracks = 12;
// A cut keeps at least this fraction of the last trial and at most kLongestCut of it.
constexpr double kShortestCut = 0.1, kLongestCut = 0.5;
// Plain steps after a failed line search or a K that did not factor.
constexpr int kFallbackSteps = 3;
// Line searches failed in a row before the solve gives up on Newton.
constexpr int kFailuresBeforeGivingUp = 2;

double frobenius_dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double sum = 0.0;  // a fixed order
  for (Eigen::Index c = 0; c < a.cols(); ++c) sum += a.col(c).dot(b.col(c));
  return sum;
}

double largest_row(const Eigen::MatrixXd& a) {
  double m = 0.0;
  for (Eigen::Index r = 0; r < a.rows(); ++r) m = std::max(m, a.row(r).squaredNorm());
  return std::sqrt(m);
}

// The direction: K factored with as little projected as factors, from the memory's level
// up. False when nothing factors.
bool factor_direction(FixedPointProblem& problem, const LocalFit& fit, const NewtonSettings& s, NewtonMemory& memory,
                      const std::function<void()>& stop_if_asked) {
  int& level = memory.level;
  bool factored = problem.factor_newton(fit, kProjectionLevels[level]);
  while (!factored && level + 1 < kProjectionLevelCount) {
    stop_if_asked();
    level = s.ladder ? level + 1 : kProjectionLevelCount - 1;
    factored = problem.factor_newton(fit, kProjectionLevels[level]);
  }
  return factored;
}

}  // namespace

NewtonEnd projected_newton_solve(FixedPointProblem& problem, const NewtonSettings& s, IterationPoint& point,
                                 LocalFit& fit, NewtonMemory& memory, SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  const Eigen::Index nf = y.rows();
  Eigen::MatrixXd g(nf, 3), rhs(nf, 3), b(nf, 3), delta(nf, 3), trial_y(nf, 3);
  Eigen::MatrixXd best_y;
  double best_energy = std::numeric_limits<double>::infinity();
  LocalFit trial_fit;
  result.distance_estimate = std::numeric_limits<double>::infinity();

  const std::function<void()> stop_if_asked = [&] {
    if (problem.interrupt_requested()) throw SolveInterrupted("solve interrupted");
  };
  // One evaluation of G at `at` (fitted as `at_fit`): an iteration of the solve.
  auto evaluate = [&](const Eigen::MatrixXd& at, const LocalFit& at_fit, Eigen::MatrixXd& to_rhs, Eigen::MatrixXd& to_g) {
    problem.global_step(at_fit, to_rhs, to_g);
    ++result.iterations;
    const double r = max_row_distance(to_g, at) / s.diag;
    result.residuals.push_back(r);
    return r;
  };

  while (result.iterations < s.max_iterations) {
    stop_if_asked();
    const double r = evaluate(y, fit, rhs, g);
    result.energies.push_back(point.energy);
    if (!std::isfinite(r)) {
      result.warnings.push_back("the iteration produced non-finite positions; stopped at the last finite shape");
      point.fitted = false;
      return NewtonEnd::Stopped;
    }
    if (point.fitted && r <= ConvergenceMonitor::kRoundoff) {  // a fixed point to working precision
      result.distance_estimate = r;
      result.converged = true;
      return NewtonEnd::Converged;
    }
    if (!point.fitted || memory.plain_steps_left > 0) {  // a plain local/global step
      if (memory.plain_steps_left > 0) --memory.plain_steps_left;
      y.swap(g);
      point.energy = problem.local_fit(y, fit);
      point.fitted = true;
      result.energies.back() = point.energy;
      continue;
    }
    b = rhs - problem.A() * y;  // A (G(y) - y): -gradient / 2
    if (point.energy < best_energy) {
      best_energy = point.energy;
      best_y = y;
    }

    const bool factored = factor_direction(problem, fit, s, memory, stop_if_asked);
    const bool exact = factored && memory.level == 0;
    stop_if_asked();
    bool accepted = false;
    double alpha = 1.0, step_size = std::numeric_limits<double>::infinity();
    if (factored) {
      problem.solve_newton(b, delta);
      ++result.newton_steps;
      step_size = largest_row(delta) / s.diag;
      const double slope = -2.0 * frobenius_dot(b, delta);  // dE/dalpha
      if (std::isfinite(step_size) && slope < 0.0) {
        if (s.lifted) problem.prepare_lift(fit, delta);
        for (int attempt = 0; attempt <= kBacktracks; ++attempt) {
          stop_if_asked();
          if (s.lifted)
            problem.lifted_step(fit, alpha, trial_y);
          else
            trial_y = y + alpha * delta;
          trial_fit = fit;  // its rotations start the fit
          const double trial_energy = problem.local_fit(trial_y, trial_fit);
          if (std::isfinite(trial_energy) && trial_energy <= point.energy + kArmijo * alpha * slope) {
            y.swap(trial_y);
            std::swap(fit, trial_fit);
            point.energy = trial_energy;
            result.energies.back() = point.energy;
            accepted = true;
            break;
          }
          double next = kLongestCut * alpha;  // the minimum of the quadratic through E(0), E'(0), E(alpha)
          const double curvature = trial_energy - point.energy - slope * alpha;
          if (std::isfinite(trial_energy) && curvature > 0.0) next = -slope * alpha * alpha / (2.0 * curvature);
          alpha = std::clamp(next, kShortestCut * alpha, kLongestCut * alpha);
        }
      }
    }
    if (!accepted) {
      ++result.line_search_failures;
      memory.plain_steps_left = kFallbackSteps;
      memory.candidate = false;
      point.energy = problem.local_fit(y, fit);  // the trials moved the linearization point
      if (++memory.failures >= kFailuresBeforeGivingUp) return NewtonEnd::GaveUp;
      continue;
    }
    memory.failures = 0;
    if (exact && alpha == 1.0) {
      result.distance_estimate = step_size;
      // K must factor at the point the step reached too, with a small step again (the dino
      // lift: a small step from where K factored ended 1.3e-3 from the solution, beside a saddle).
      const bool small = step_size <= s.tolerance;
      if (small && memory.candidate) {
        result.converged = true;
        return NewtonEnd::Converged;
      }
      memory.candidate = small;
    } else {
      memory.candidate = false;
    }
    if (alpha == 1.0 && memory.level > 0) memory.level = s.ladder ? memory.level - 1 : 0;  // the model held: project less
  }
  // Out of iterations: never end worse than the best point held.
  if (best_y.size() != 0 && point.fitted) {
    if (best_energy < point.energy) {
      y = best_y;
      point.energy = problem.local_fit(y, fit);
      if (!result.energies.empty()) result.energies.back() = point.energy;
      result.warnings.push_back("the last iterates were worse than an earlier one; returned the best");
    }
  }
  result.warnings.push_back(
      not_converged_warning(s.max_iterations, result.distance_estimate, s.tolerance, "the last Newton step was"));
  return NewtonEnd::Stopped;
}

}  // namespace edgedeform
