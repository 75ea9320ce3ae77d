#include "edgedeform/direct_newton.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"

namespace edgedeform {

namespace {

constexpr double kArmijo = 1e-4;
constexpr int kBacktracks = 12;
// A cut is at least this fraction of the last trial and at most kLongestCut of it.
constexpr double kShortestCut = 0.1, kLongestCut = 0.5;
// Plain steps after a failed line search or a K that did not factor.
constexpr int kFallbackSteps = 3;

double frobenius_dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double sum = 0.0;  // a fixed order
  for (Eigen::Index c = 0; c < a.cols(); ++c) sum += a.col(c).dot(b.col(c));
  return sum;
}

bool tracing() {
  static const bool on = std::getenv("EDGEDEFORM_TRACE") != nullptr;
  return on;
}

}  // namespace

void direct_newton_solve(FixedPointProblem& problem, const DirectNewtonSettings& s, DirectNewtonPoint point,
                         SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  const Eigen::Index nf = y.rows();
  Eigen::MatrixXd g(nf, 3), rhs(nf, 3), b(nf, 3), delta(nf, 3), trial_g(nf, 3), trial_rhs(nf, 3), trial_y(nf, 3);
  Eigen::MatrixXd best_y;
  double best_merit = std::numeric_limits<double>::infinity();
  LocalFit trial_fit, corrected_fit;
  Eigen::MatrixXd b_trial(nf, 3), correction(nf, 3);
  bool have_g = false;  // g, rhs already hold G(y): a line-search trial that was kept
  DirectNewtonMemory& memory = point.memory;
  result.distance_estimate = std::numeric_limits<double>::infinity();

  auto stop_if_asked = [&] {
    if (problem.interrupt_requested()) {
      point.fitted = false;
      throw SolveInterrupted("solve interrupted");
    }
  };
  auto evaluate = [&](const Eigen::MatrixXd& at, const LocalFit& fit, Eigen::MatrixXd& to_rhs, Eigen::MatrixXd& to_g) {
    problem.global_step(fit, to_rhs, to_g);
    ++result.iterations;
    const double r = max_row_distance(to_g, at) / s.diag;
    result.residuals.push_back(r);
    return r;
  };

  while (result.iterations < s.max_iterations) {
    stop_if_asked();
    if (!have_g) {
      const double r0 = evaluate(y, point.fit, rhs, g);
      result.energies.push_back(point.energy);
      if (!std::isfinite(r0)) {
        result.warnings.push_back("the iteration produced non-finite positions; stopped at the last finite shape");
        point.fitted = false;
        return;
      }
    }
    have_g = false;
    const double r = result.residuals.back();
    if (point.fitted && r <= ConvergenceMonitor::kRoundoff) {  // a fixed point to working precision
      result.distance_estimate = r;
      result.converged = true;
      return;
    }
    // No iteration left for a trial's G (lambda < 1): a plain step, so that calls of one
    // iteration each (a live tick on a slow machine) still move.
    const bool no_trial_left = !s.descent && result.iterations >= s.max_iterations;
    if (!point.fitted || memory.plain_steps_left > 0 || no_trial_left) {  // a plain local/global step
      if (memory.plain_steps_left > 0) --memory.plain_steps_left;
      y.swap(g);
      point.energy = problem.local_fit(y, point.fit);
      point.fitted = true;
      result.energies.back() = point.energy;
      continue;
    }
    b = rhs - problem.A() * y;  // A (G(y) - y): -gradient / 2 at lambda = 1
    const double b_norm = b.norm();
    const double merit = s.descent ? point.energy : b_norm;
    if (merit < best_merit) {
      best_merit = merit;
      best_y = y;
    }

    // The step: K with as little projected as factors (lambda = 1), K itself otherwise.
    int& level = memory.level;
    if (!s.descent) level = 0;
    bool factored = problem.factor_newton(point.fit, kProjectionLevels[level]);
    while (!factored && s.descent && level + 1 < kProjectionLevelCount) {
      stop_if_asked();
      level = s.ladder ? level + 1 : kProjectionLevelCount - 1;
      factored = problem.factor_newton(point.fit, kProjectionLevels[level]);
      memory.held = 0;
    }
    const bool model = level > 0;
    stop_if_asked();
    bool accepted = false, extrapolated = false;
    double alpha = 1.0, step_size = std::numeric_limits<double>::infinity();
    if (factored) {
      problem.solve_newton(b, delta);
      ++result.newton_steps;
      step_size = max_row_distance(delta, Eigen::MatrixXd::Zero(nf, 3)) / s.diag;
      const double slope = -2.0 * frobenius_dot(b, delta);  // dE/dalpha at lambda = 1
      if (std::isfinite(step_size) && (!s.descent || slope < 0.0)) {
        const bool lifted = s.descent && s.correction == 3;
        if (lifted) problem.prepare_lift(point.fit, delta);
        for (int attempt = 0; attempt <= kBacktracks && (s.descent || result.iterations < s.max_iterations);
             ++attempt) {
          stop_if_asked();
          if (lifted)
            problem.lifted_step(point.fit, alpha, trial_y);
          else
            trial_y = y + alpha * delta;
          trial_fit = point.fit;  // its rotations start the fit
          const double trial_energy = problem.local_fit(trial_y, trial_fit);
          double next_alpha = kLongestCut * alpha;
          bool keep = false;
          double kept_energy = trial_energy;
          if (s.descent) {
            keep = std::isfinite(trial_energy) && trial_energy <= point.energy + kArmijo * alpha * slope;
            if (!keep && std::isfinite(trial_energy)) {  // the minimum of the quadratic through E(0), E'(0), E(alpha)
              const double curvature = trial_energy - point.energy - slope * alpha;
              if (curvature > 0.0) next_alpha = -slope * alpha * alpha / (2.0 * curvature);
            }
            if (!keep && std::isfinite(trial_energy) && (s.correction == 1 || s.correction == 2) &&
                result.iterations < s.max_iterations) {
              // A second-order correction: the trial's stiff (stretch) error, which a
              // step along a turning part's tangent makes, removed by one plain step
              // (E never rises there) or one chord step with the same factor.
              evaluate(trial_y, trial_fit, trial_rhs, trial_g);
              if (s.correction == 2) {
                b_trial = trial_rhs - problem.A() * trial_y;
                problem.solve_newton(b_trial, correction);
                trial_g = trial_y + correction;
              }
              corrected_fit = trial_fit;
              const double corrected = problem.local_fit(trial_g, corrected_fit);
              keep = std::isfinite(corrected) && corrected <= point.energy + kArmijo * alpha * slope;
              result.energies.push_back(keep ? corrected : point.energy);
              if (keep) {
                trial_y.swap(trial_g);
                std::swap(trial_fit, corrected_fit);
                kept_energy = corrected;
                ++result.corrections;
              }
            }
          } else if (std::isfinite(trial_energy)) {
            const double trial_r = evaluate(trial_y, trial_fit, trial_rhs, trial_g);
            keep = std::isfinite(trial_r) &&
                   (trial_rhs - problem.A() * trial_y).norm() <= (1.0 - kArmijo * alpha) * b_norm;
            result.energies.push_back(keep ? trial_energy : point.energy);
          }
          if (keep) {
            y.swap(trial_y);
            std::swap(point.fit, trial_fit);
            point.energy = kept_energy;
            if (s.descent) {
              result.energies.back() = point.energy;
            } else {
              g.swap(trial_g);
              rhs.swap(trial_rhs);
              have_g = true;
            }
            accepted = true;
            // A projected model is stiffer than K along the soft modes: its full step may
            // stop short. Go on along it while E keeps falling.
            if (s.descent && s.extrapolate && level > 0 && alpha == 1.0 && kept_energy == trial_energy) {
              double reached = 1.0;
              while (reached < s.extrapolate) {
                stop_if_asked();
                trial_y = y + reached * delta;  // y = start + reached delta: twice as far
                trial_fit = point.fit;
                const double farther = problem.local_fit(trial_y, trial_fit);
                if (!(std::isfinite(farther) && farther < point.energy)) break;
                y.swap(trial_y);
                std::swap(point.fit, trial_fit);
                point.energy = farther;
                result.energies.back() = farther;
                reached *= 2.0;
              }
              alpha = reached;
              extrapolated = reached > 1.0;
            }
            break;
          }
          alpha = std::clamp(next_alpha, kShortestCut * alpha, kLongestCut * alpha);
        }
      }
    }
    if (tracing())
      std::fprintf(stderr, "direct newton %d (projection %.2f): r %.2e |b| %.2e step %.2e alpha %.3g %s E %.10g\n",
                   result.newton_steps, kProjectionLevels[level], r, b_norm, step_size, alpha,
                   !factored ? "not factored" : accepted ? "kept" : "failed", point.energy);
    if (accepted) {
      if (!model && alpha == 1.0 && !extrapolated) {
        result.distance_estimate = step_size;
        // lambda < 1: the kept trial's own residual must agree. lambda = 1: K must also factor
        // at the point the step reached, with a small step again: where K is positive
        // definite only very near the solution, a small step from a point where it factors
        // can still end beside a saddle (measured: the dino lift, 2.7e-4 of the diagonal).
        const bool small = step_size <= s.tolerance && (s.descent || result.residuals.back() <= s.tolerance);
        if (small && (!s.descent || memory.candidate)) {
          result.converged = true;
          return;
        }
        memory.candidate = small;
      } else {
        memory.candidate = false;
      }
      // The model held: project less, after a few such steps (a level that does not factor
      // costs a factorization to find out).
      if (alpha >= 1.0 && ++memory.held >= s.level_patience && level > 0) {
        level = s.ladder ? level - 1 : 0;
        memory.held = 0;
      } else if (alpha < 1.0) {
        memory.held = 0;
      }
    } else {
      ++result.line_search_failures;
      memory.plain_steps_left = kFallbackSteps;
      memory.candidate = false;
      point.energy = problem.local_fit(y, point.fit);  // the trials moved the linearization point
    }
  }
  // Out of iterations: never end worse than the best point held.
  if (best_y.size() != 0 && point.fitted) {
    double merit = point.energy;
    if (!s.descent) {
      problem.global_step(point.fit, rhs, g);
      merit = (rhs - problem.A() * y).norm();
    }
    if (best_merit < merit) {
      y = best_y;
      point.energy = problem.local_fit(y, point.fit);
      if (!result.energies.empty()) result.energies.back() = point.energy;
      result.warnings.push_back("the last iterates were worse than an earlier one; returned the best");
    }
  }
  std::ostringstream msg;
  msg << "not converged: stopped at max_iterations (" << s.max_iterations << "); ";
  if (std::isfinite(result.distance_estimate))
    msg << "the last Newton step was " << result.distance_estimate << " of the bounding-box diagonal (tolerance "
        << s.tolerance << ")";
  else
    msg << "the distance to the fixed point is unknown (tolerance " << s.tolerance << " of the bounding-box diagonal)";
  result.warnings.push_back(msg.str());
}

}  // namespace edgedeform
