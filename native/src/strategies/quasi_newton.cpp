#include "strategies/quasi_newton.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "strategies/claim_check.h"
#include "strategies/global_step.h"
#include "base/errors.h"

namespace edgedeform {

namespace {
// Armijo's sufficient decrease, as a fraction of the slope.
constexpr double kArmijo = 1e-4;
// The longest step the line search tries, in units of the quasi-Newton step: along a flat
// valley the scaled step is still far too short (record 0070: most steps of the Spot swing
// were taken longer).
constexpr double kLongestStep = 64.0;
// Longer steps tried after the first passed; shorter ones tried before the direction gives
// way to the plain step (which never raises E).
constexpr int kLongerTries = 3;
constexpr int kShorterTries = 2;
// A pair is kept only when its curvature s . y is positive by this relative margin.
constexpr double kCurvatureFloor = 1e-10;

double dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) { return (a.array() * b.array()).sum(); }

// The minimum along the line of the parabola with E(0) = e0, E'(0) = slope (< 0) and
// E(alpha) = e: infinite where that parabola does not curve upwards.
double parabola_minimum(double e0, double slope, double alpha, double e) {
  const double curvature = (e - e0 - slope * alpha) / (alpha * alpha);
  return curvature > 0.0 ? -slope / (2.0 * curvature) : std::numeric_limits<double>::infinity();
}

// grad = -2 A F: the gradient of E at y, whose plain step is F = G(y) - y.
void energy_gradient(const FixedPointProblem& problem, const Eigen::MatrixXd& F, Eigen::MatrixXd& grad) {
  grad.noalias() = problem.A() * F;
  grad *= -2.0;
}
}  // namespace

void QuasiNewtonMemory::restart(int free_vertices) {
  drop_pairs();
  has_last_ = false;
  monitor_.resize(free_vertices);
}

void QuasiNewtonMemory::forget() {
  drop_pairs();
  has_last_ = false;
  monitor_.reset();
}

void QuasiNewtonMemory::add_point(const Eigen::MatrixXd& y, const Eigen::MatrixXd& grad, const Eigen::MatrixXd& F) {
  if (has_last_) {
    Pair& p = pairs_[static_cast<size_t>(next_)];
    p.s = y - last_y_;
    p.y = grad - last_grad_;
    const double sy = dot(p.s, p.y);
    if (sy > kCurvatureFloor * p.s.norm() * p.y.norm()) {
      p.h0y = last_F_ - F;  // H0 (grad - last_grad) = (2A)^-1 (-2A)(F - last_F)
      p.rho = 1.0 / sy;
      next_ = (next_ + 1) % kPairs;
      count_ = std::min(count_ + 1, kPairs);
    }
  }
  last_y_ = y;
  last_grad_ = grad;
  last_F_ = F;
  has_last_ = true;
}

void QuasiNewtonMemory::direction(const Eigen::MatrixXd& grad, const Eigen::MatrixXd& F, Eigen::MatrixXd& out) {
  // The two-loop recursion, newest pair first, with H0 q = F - sum a_i H0 y_i.
  alpha_.assign(static_cast<size_t>(count_), 0.0);
  Eigen::MatrixXd& q = z_;
  q = -grad;
  out = F;
  for (int k = 0; k < count_; ++k) {
    const Pair& p = pairs_[static_cast<size_t>((next_ - 1 - k + kPairs) % kPairs)];
    const double a = p.rho * dot(p.s, q);
    alpha_[static_cast<size_t>(k)] = a;
    q -= a * p.y;
    out -= a * p.h0y;
  }
  if (count_ > 0) {  // Shanno-Phua: H0 scaled to the curvature of the newest pair
    const Pair& newest = pairs_[static_cast<size_t>((next_ - 1 + kPairs) % kPairs)];
    out *= dot(newest.s, newest.y) / dot(newest.y, newest.h0y);
  }
  for (int k = count_ - 1; k >= 0; --k) {
    const Pair& p = pairs_[static_cast<size_t>((next_ - 1 - k + kPairs) % kPairs)];
    const double b = p.rho * dot(p.y, out);
    out += (alpha_[static_cast<size_t>(k)] - b) * p.s;
  }
}

// Each iteration: g = G(y), the residual and the distance estimate (converged: g is the
// result, as for the plain and Anderson strategy); then the gradient -2 A (g - y), a pair
// from the last point, the L-BFGS direction d, and a line search on E along y + alpha d
// (Armijo at alpha = 1, then longer while a parabola says so and E falls; else shorter). A
// direction that is not downhill or fails its line search gives way to the plain step g,
// which never raises E at lambda = 1 (block descent), and the pairs are dropped. The first
// step of a cold start (fit not y's: R = I, s = 1) is a plain step.
void quasi_newton_solve(FixedPointProblem& problem, const QuasiNewtonSettings& settings, IterationPoint& point,
                        LocalFit& fit, QuasiNewtonMemory& m, SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  start_history(result, settings.max_iterations);

  for (int k = 0; k < settings.max_iterations; ++k) {
    if (problem.interrupt_requested()) throw SolveInterrupted("solve interrupted");
    double r = 0.0;
    if (!recorded_global_step(problem, fit, point, settings.diag, m.rhs_, m.g_, r, result)) return;
    const bool map_pair = point.fitted;  // g = G(y)
    result.distance_estimate = checked_distance(problem, m.monitor_, fit, y, m.g_, r, map_pair,
                                                settings.verify_claims, settings.tolerance, result);
    if (result.distance_estimate < settings.tolerance || !map_pair) {  // the plain step
      y.swap(m.g_);
      point.energy = problem.local_fit(y, fit);
      result.energies.push_back(point.energy);
      point.fitted = true;
      if (result.distance_estimate < settings.tolerance) {
        result.converged = true;
        return;
      }
      continue;
    }

    m.F_ = m.g_ - y;
    energy_gradient(problem, m.F_, m.grad_);
    m.add_point(y, m.grad_, m.F_);
    m.direction(m.grad_, m.F_, m.d_);
    double slope = dot(m.grad_, m.d_);
    bool taken = false;
    if (slope < 0.0) {
      double alpha = 1.0;
      m.z_ = y + m.d_;
      double e = problem.local_fit(m.z_, m.trial_);
      if (e <= point.energy + kArmijo * slope) {
        taken = true;
        // Longer while the parabola through E(0), E'(0) and the last trial puts the minimum
        // at least twice as far: one fit per try, none where the step is about right.
        for (int tries = 0; tries < kLongerTries; ++tries) {
          const double longer = std::min(parabola_minimum(point.energy, slope, alpha, e), kLongestStep);
          if (!(longer >= 2.0 * alpha)) break;
          m.z_ = y + longer * m.d_;
          const double e2 = problem.local_fit(m.z_, m.scratch_);
          ++result.line_search_fits;
          if (!(e2 < e)) break;
          alpha = longer;
          e = e2;
          std::swap(m.trial_, m.scratch_);
        }
      } else {
        for (int h = 0; h < kShorterTries && !taken; ++h) {
          alpha = std::clamp(parabola_minimum(point.energy, slope, alpha, e), 0.1 * alpha, 0.5 * alpha);
          m.z_ = y + alpha * m.d_;
          e = problem.local_fit(m.z_, m.trial_);
          ++result.line_search_fits;
          taken = e <= point.energy + kArmijo * alpha * slope;
        }
      }
      if (taken) {
        ++result.accelerated_steps;
        y += alpha * m.d_;
        std::swap(fit, m.trial_);
        point.energy = e;
      } else {
        ++result.line_search_fits;  // the failed first trial
      }
    }
    if (!taken) {  // the plain step; the pairs no longer help
      ++result.rejected_steps;
      m.drop_pairs();
      y.swap(m.g_);
      point.energy = problem.local_fit(y, fit);
    }
    result.energies.push_back(point.energy);
  }
  result.warnings.push_back(not_converged_warning(settings.max_iterations, result.distance_estimate, settings.tolerance,
                                                  "the estimated distance to the fixed point is",
                                                  "the iteration has not been seen to contract"));
}

}  // namespace edgedeform
