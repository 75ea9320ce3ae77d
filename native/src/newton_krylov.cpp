#include "edgedeform/newton_krylov.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <limits>
#include <sstream>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "edgedeform/fgmres.h"

namespace edgedeform {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

// Eisenstat & Walker (1996), choice 2: eta_k = gamma (|F_k| / |F_k-1|)^2, safeguarded.
constexpr double kForcingGamma = 0.9;
constexpr double kForcingMax = 0.5;
constexpr double kForcingMin = 0.01;
// Near the solution (a step below this many tolerances) the step must be solved this well:
// its size is then the distance estimate.
constexpr double kNearSteps = 10.0;
constexpr double kNearForcing = 0.05;
constexpr double kArmijo = 1e-4;
constexpr int kBacktracks = 6;
// Plain steps after a failed line search before Newton is tried again.
constexpr int kFallbackSteps = 3;

double frobenius_dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double sum = 0.0;  // a fixed order
  for (Eigen::Index c = 0; c < a.cols(); ++c) sum += a.col(c).dot(b.col(c));
  return sum;
}

Eigen::Map<const Eigen::MatrixXd> as_matrix(const Eigen::VectorXd& v, Eigen::Index rows) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), rows, 3);
}

}  // namespace

void newton_krylov_solve(FixedPointProblem& problem, const NewtonSettings& s, IterationPoint point, SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  const Eigen::Index nf = y.rows();
  Eigen::MatrixXd g(nf, 3), rhs(nf, 3), b(nf, 3), trial_g(nf, 3), trial_rhs(nf, 3), trial_y(nf, 3);
  Eigen::MatrixXd best_y;
  double best_merit = std::numeric_limits<double>::infinity();
  LocalFit trial_fit;
  bool have_g = false;          // g, rhs already hold G(y) (a line-search trial that was kept)
  int plain_left = s.plain_steps_first;
  double previous_b_norm = -1.0, previous_eta = kForcingMax;
  double last_step = std::numeric_limits<double>::infinity();  // |delta|_inf / diag of the last full step
  bool last_step_full = false;
  result.distance_estimate = std::numeric_limits<double>::infinity();

  auto finish_unconverged = [&](const std::string& why) {
    std::ostringstream msg;
    msg << "not converged: " << why << "; ";
    if (std::isfinite(result.distance_estimate))
      msg << "the estimated distance to the fixed point is " << result.distance_estimate
          << " of the bounding-box diagonal (tolerance " << s.tolerance << ")";
    else
      msg << "the distance to the fixed point is unknown (tolerance " << s.tolerance << " of the bounding-box diagonal)";
    result.warnings.push_back(msg.str());
  };

  while (result.iterations < s.max_iterations) {
    if (problem.interrupt_requested()) {
      point.fitted = false;
      throw SolveInterrupted("solve interrupted");
    }
    if (!have_g) {
      problem.global_step(point.fit, rhs, g);
      ++result.iterations;
      const double r0 = max_row_distance(g, y) / s.diag;
      result.residuals.push_back(r0);
      if (!std::isfinite(r0)) {
        result.warnings.push_back("the iteration produced non-finite positions; stopped at the last finite shape");
        result.energies.push_back(point.energy);
        point.fitted = false;
        return;
      }
      result.energies.push_back(point.energy);
    }
    have_g = false;
    const double r = result.residuals.back();
    const bool map_pair = point.fitted;
    b = rhs - problem.A() * y;  // A (G(y) - y): the Newton step's right side, -gradient / 2 at lambda = 1
    const double b_norm = b.norm();
    if (map_pair) {
      const double merit = s.descent ? point.energy : b_norm;
      if (merit < best_merit) {
        best_merit = merit;
        best_y = y;
      }
      // The last full Newton step was solved tightly and was small, and G barely moves y:
      // y is within about that step of the fixed point (quadratic convergence).
      if (last_step_full && last_step <= s.tolerance && r <= s.tolerance) {
        result.distance_estimate = std::max(last_step, r);
        result.converged = true;
        return;
      }
    }
    if (!map_pair || plain_left > 0) {  // a plain local/global step
      if (plain_left > 0) --plain_left;
      y.swap(g);
      point.energy = problem.local_fit(y, point.fit);
      point.fitted = true;
      last_step_full = false;
      result.energies.back() = point.energy;
      continue;
    }

    // The Newton step.
    auto t0 = Clock::now();
    std::unique_ptr<FixedPointLinearization> lin = problem.linearize(point.fit);
    result.linearize_ms += ms_since(t0);
    t0 = Clock::now();
    CoarseCorrection coarse;
    if (s.coarse && s.coarse_stiffness && s.coarse->dimension() > 0) {
      if (coarse.factor(*s.coarse, coarse_operator(*s.coarse, *s.coarse_stiffness, *lin))) ++result.coarse_factorizations;
    }
    result.coarse_ms += ms_since(t0);
    t0 = Clock::now();
    double eta = kForcingMax;
    if (previous_b_norm > 0.0) {
      eta = kForcingGamma * std::pow(b_norm / previous_b_norm, 2);
      const double floor = kForcingGamma * previous_eta * previous_eta;
      if (floor > 0.1) eta = std::max(eta, floor);
    }
    eta = std::clamp(eta, kForcingMin, kForcingMax);
    if (last_step <= kNearSteps * s.tolerance) eta = std::min(eta, kNearForcing);
    previous_b_norm = b_norm;
    previous_eta = eta;

    Eigen::MatrixXd product(nf, 3), zc(nf, 3), residual(nf, 3), fine(nf, 3);
    const LinearMap K = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
      lin->newton_operator(as_matrix(in, nf), product);
      out = Eigen::Map<const Eigen::VectorXd>(product.data(), product.size());
    };
    // Two levels, multiplicative: the coarse correction, then A^-1 on what it leaves.
    const LinearMap precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
      const auto r_in = as_matrix(in, nf);
      if (coarse.ready()) {
        coarse.apply(r_in, zc);
        lin->newton_operator(zc, product);
        residual = r_in - product;
        problem.solve_A(residual, fine);
        fine += zc;
      } else {
        problem.solve_A(r_in, fine);
      }
      out = Eigen::Map<const Eigen::VectorXd>(fine.data(), fine.size());
    };
    Eigen::VectorXd delta_vector;
    const Eigen::VectorXd b_vector = Eigen::Map<const Eigen::VectorXd>(b.data(), b.size());
    const KrylovResult krylov = fgmres(K, precondition, b_vector, delta_vector, eta, s.krylov_iterations,
                                       [&] { return problem.interrupt_requested(); });
    result.krylov_ms += ms_since(t0);
    ++result.newton_steps;
    result.krylov_iterations += krylov.iterations;
    if (std::getenv("EDGEDEFORM_TRACE"))
      std::fprintf(stderr, "newton %d: |b| %.3e eta %.3f krylov %d rel %.3e\n", result.newton_steps, b_norm, eta,
                   krylov.iterations, krylov.relative_residual);
    if (problem.interrupt_requested()) {
      point.fitted = false;
      throw SolveInterrupted("solve interrupted");
    }
    const Eigen::MatrixXd delta = as_matrix(delta_vector, nf);
    const double step_size = max_row_distance(delta, Eigen::MatrixXd::Zero(nf, 3)) / s.diag;

    // Line search.
    bool accepted = false;
    double alpha = 1.0;
    const double slope = -2.0 * frobenius_dot(b, delta);  // dE/dalpha at lambda = 1
    if (std::isfinite(step_size) && (!s.descent || slope < 0.0)) {
      for (int attempt = 0; attempt <= kBacktracks && result.iterations < s.max_iterations; ++attempt, alpha *= 0.5) {
        trial_y = y + alpha * delta;
        trial_fit = point.fit;  // warm rotations for the fit
        const double trial_energy = problem.local_fit(trial_y, trial_fit);
        if (!std::isfinite(trial_energy)) continue;
        if (s.descent) {
          if (trial_energy <= point.energy + kArmijo * alpha * slope) {
            y.swap(trial_y);
            std::swap(point.fit, trial_fit);
            point.energy = trial_energy;
            result.energies.back() = point.energy;
            accepted = true;
            break;
          }
        } else {
          problem.global_step(trial_fit, trial_rhs, trial_g);
          ++result.iterations;
          const double trial_r = max_row_distance(trial_g, trial_y) / s.diag;
          result.residuals.push_back(trial_r);
          const double trial_b_norm = (trial_rhs - problem.A() * trial_y).norm();
          if (std::isfinite(trial_r) && trial_b_norm <= (1.0 - kArmijo * alpha) * b_norm) {
            y.swap(trial_y);
            std::swap(point.fit, trial_fit);
            point.energy = trial_energy;
            g.swap(trial_g);
            rhs.swap(trial_rhs);
            have_g = true;
            accepted = true;
            result.energies.push_back(point.energy);
            break;
          }
          result.energies.push_back(point.energy);
        }
      }
    }
    if (std::getenv("EDGEDEFORM_TRACE"))
      std::fprintf(stderr, "   step %.3e alpha %.3f accepted %d r %.3e E %.8g\n", step_size, alpha, accepted, r, point.energy);
    if (accepted) {
      last_step_full = alpha == 1.0 && krylov.converged;
      last_step = last_step_full ? step_size : std::numeric_limits<double>::infinity();
      result.distance_estimate = step_size;
    } else {
      ++result.line_search_failures;
      plain_left = kFallbackSteps;
      last_step_full = false;
      last_step = std::numeric_limits<double>::infinity();
      point.energy = problem.local_fit(y, point.fit);  // the trials moved the linearization point
      have_g = false;
    }
  }
  // Out of iterations: never end worse than the best point held.
  if (best_y.size() != 0 && point.fitted) {
    double merit = point.energy;
    if (!s.descent) {  // |A F| of the point held (not yet evaluated when the last step moved it)
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
  finish_unconverged("stopped at max_iterations (" + std::to_string(s.max_iterations) + ")");
}

}  // namespace edgedeform
