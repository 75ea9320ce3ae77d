#include "edgedeform/newton_krylov.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"
#include "edgedeform/fgmres.h"

namespace edgedeform {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }

// Eisenstat & Walker (1996), choice 2: eta_k = gamma (|F_k| / |F_k-1|)^2, safeguarded, at
// most kForcingMax (measured, Spot lift, edge, lambda 1: 0.5 took 14 Newton steps, 0.1 11).
constexpr double kForcingGamma = 0.9;
constexpr double kForcingMax = 0.1;
constexpr double kForcingMin = 0.01;
// A step that may end the solve is solved this well: near the solution (the last full
// Newton step below kNearSteps tolerances) the soft modes must be resolved, since the step's
// size is then the distance estimate. Measured on Spot (edge, lambda 1): steps solved to
// 0.05 claimed 8.6e-4 of the diagonal while 4.1e-3 away. Not sooner: on the koala (50k)
// the residual |G(y) - y| fell below the tolerance while y was still far away, and every
// step then spent its 30 products on a tight solve that stalled at 0.04-0.6.
constexpr double kNearSteps = 1.0;
constexpr double kVerifyForcing = 1e-3;
constexpr double kArmijo = 1e-4;
constexpr int kBacktracks = 6;
// lambda = 1: the positive model gives way to the true Hessian once its full step is below
// this many tolerances.
constexpr double kModelToNewton = 10.0;
// Plain steps after a failed line search before Newton is tried again.
constexpr int kFallbackSteps = 3;
// The Levenberg-Marquardt shift (relative to A): 0 at first (measured on the Spot lift,
// edge, lambda 1: starting at 1, 0.1 or 0.01 took 19, 15 and 11 Newton steps, 0 took 11
// with the fewest products), raised after a backtracked step, relaxed by kShiftRelax after
// a full one, and 0 again below kShiftFloor.

constexpr double kShiftRelax = 10.0;
constexpr double kShiftRaise = 4.0;
constexpr double kShiftFloor = 1e-3;
// The coarse operator is refactored at least every this many Newton steps (it is lagged in
// between), and whenever the shift moved by more than kCoarseShiftRatio.
constexpr int kCoarseLag = 3;
constexpr double kCoarseShiftRatio = 3.0;

double frobenius_dot(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double sum = 0.0;  // a fixed order
  for (Eigen::Index c = 0; c < a.cols(); ++c) sum += a.col(c).dot(b.col(c));
  return sum;
}

double largest_row_norm(const Eigen::MatrixXd& a) {
  double m = 0.0;
  for (Eigen::Index r = 0; r < a.rows(); ++r) m = std::max(m, a.row(r).squaredNorm());
  return std::sqrt(m);
}

Eigen::Map<const Eigen::MatrixXd> as_matrix(const Eigen::VectorXd& v, Eigen::Index rows) {
  return Eigen::Map<const Eigen::MatrixXd>(v.data(), rows, 3);
}

bool tracing() {
  static const bool on = std::getenv("EDGEDEFORM_TRACE") != nullptr;
  return on;
}

}  // namespace

void newton_krylov_solve(FixedPointProblem& problem, const NewtonSettings& s, IterationPoint point, SolveResult& result) {
  Eigen::MatrixXd& y = point.y;
  const Eigen::Index nf = y.rows();
  Eigen::MatrixXd g(nf, 3), rhs(nf, 3), b(nf, 3), trial_g(nf, 3), trial_rhs(nf, 3), trial_y(nf, 3);
  Eigen::MatrixXd product(nf, 3), coarse_part(nf, 3), remainder(nf, 3), fine(nf, 3), best_y;
  double best_merit = std::numeric_limits<double>::infinity();
  LocalFit trial_fit;
  bool have_g = false;  // g, rhs already hold G(y): a line-search trial that was kept
  // What the strategy carries from one call to the next (a warm solve with still targets
  // continues it): see NewtonMemory.
  NewtonMemory& memory = point.memory;
  int& plain_left = memory.plain_steps_left;
  double& previous_b_norm = memory.previous_b_norm;
  double& previous_eta = memory.previous_eta;
  double& last_exact_step = memory.last_exact_step;
  double& shift = memory.shift;
  bool& near_minimum = memory.near_minimum;
  int& coarse_age = memory.coarse_age;
  double& coarse_shift = memory.coarse_shift;
  CoarseCorrection* coarse = s.coarse_correction;
  result.distance_estimate = std::numeric_limits<double>::infinity();

  auto stop_if_asked = [&] {
    if (problem.interrupt_requested()) {
      point.fitted = false;
      throw SolveInterrupted("solve interrupted");
    }
  };
  // One evaluation of G at `at` (fitted as `fit`): an iteration of the solve.
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
    // No iteration left in this call for a trial's G (lambda < 1): a plain step, so that
    // calls of one iteration each (a live tick on a slow machine) still move.
    const bool no_trial_left = !s.descent && result.iterations >= s.max_iterations;
    if (!point.fitted || plain_left > 0 || no_trial_left) {  // a plain local/global step
      if (plain_left > 0) --plain_left;
      y.swap(g);
      point.energy = problem.local_fit(y, point.fit);
      point.fitted = true;
      result.energies.back() = point.energy;
      continue;
    }
    b = rhs - problem.A() * y;  // A (G(y) - y): the right side, -gradient / 2 at lambda = 1
    const double b_norm = b.norm();
    const double merit = s.descent ? point.energy : b_norm;
    if (merit < best_merit) {
      best_merit = merit;
      best_y = y;
    }

    // The linearization and, lagged, its coarse operator.
    auto t0 = Clock::now();
    const bool positive_model = s.descent && !near_minimum;
    const std::unique_ptr<FixedPointLinearization> lin = problem.linearize(point.fit, positive_model);
    result.linearize_ms += ms_since(t0);
    const double step_shift = shift;
    t0 = Clock::now();
    if (coarse && s.coarse && s.coarse_stiffness) {
      const bool shift_moved = coarse_shift < 0.0 || (step_shift == 0.0) != (coarse_shift == 0.0) ||
                               std::max(step_shift, coarse_shift) > kCoarseShiftRatio * std::min(step_shift, coarse_shift);
      // Assembly (the costly part) follows the linearization, lagged; a new shift alone
      // only refactors the assembled operator plus shift * U^T A U.
      const bool reassemble = memory.coarse_unshifted.rows() == 0 || !coarse->ready() || ++coarse_age >= kCoarseLag;
      if (reassemble) {
        memory.coarse_unshifted = coarse_operator(*s.coarse, *s.coarse_stiffness, *lin);
        coarse_age = 0;
      }
      if (reassemble || shift_moved) {
        SparseMatrix C = memory.coarse_unshifted;
        if (step_shift > 0.0) C += step_shift * *s.coarse_stiffness;
        if (coarse->factor(*s.coarse, C)) ++result.coarse_factorizations;
        coarse_shift = step_shift;
      }
    }
    result.coarse_ms += ms_since(t0);

    // Forcing term; a tight one where the step may end the solve.
    const bool exact = step_shift == 0.0 && !positive_model;
    double eta = kForcingMax;
    if (previous_b_norm > 0.0) {
      eta = kForcingGamma * std::pow(b_norm / previous_b_norm, 2);
      const double floor = kForcingGamma * previous_eta * previous_eta;
      if (floor > 0.1) eta = std::max(eta, floor);
    }
    eta = std::clamp(eta, kForcingMin, kForcingMax);
    if (exact && last_exact_step <= kNearSteps * s.tolerance) eta = kVerifyForcing;
    previous_b_norm = b_norm;
    previous_eta = eta;

    // (K + shift A) delta = b by FGMRES, right-preconditioned with two levels
    // (multiplicative: the coarse correction, then A^-1 on what it leaves).
    const auto apply_operator = [&](const Eigen::MatrixXd& in, Eigen::MatrixXd& out) {
      lin->newton_operator(in, out);
      if (step_shift > 0.0) out.noalias() += step_shift * (problem.A() * in);
    };
    const LinearMap K = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
      apply_operator(as_matrix(in, nf), product);
      out = Eigen::Map<const Eigen::VectorXd>(product.data(), product.size());
    };
    const LinearMap precondition = [&](const Eigen::VectorXd& in, Eigen::VectorXd& out) {
      const auto r_in = as_matrix(in, nf);
      if (coarse && coarse->ready()) {  // multiplicative: the additive form took 2x the products (Spot)
        coarse->apply(r_in, coarse_part);
        apply_operator(coarse_part, product);
        remainder = r_in - product;
        problem.solve_A(remainder, fine);
        fine += coarse_part;
      } else {
        problem.solve_A(r_in, fine);
      }
      out = Eigen::Map<const Eigen::VectorXd>(fine.data(), fine.size());
    };
    t0 = Clock::now();
    Eigen::VectorXd delta_vector;
    const KrylovResult krylov = fgmres(K, precondition, Eigen::Map<const Eigen::VectorXd>(b.data(), b.size()),
                                       delta_vector, eta, s.krylov_iterations, [&] { return problem.interrupt_requested(); });
    result.krylov_ms += ms_since(t0);
    ++result.newton_steps;
    result.krylov_iterations += krylov.iterations;
    stop_if_asked();
    const Eigen::MatrixXd delta = as_matrix(delta_vector, nf);
    const double step_size = largest_row_norm(delta) / s.diag;
    // A step that ends the solve: Newton's own, solved tightly, and small.
    const bool final_step = exact && krylov.converged && eta <= kVerifyForcing && step_size <= s.tolerance;

    // Line search.
    bool accepted = false;
    double alpha = 1.0;
    const double slope = -2.0 * frobenius_dot(b, delta);  // dE/dalpha at lambda = 1
    if (std::isfinite(step_size) && (!s.descent || slope < 0.0)) {
      for (int attempt = 0; attempt <= kBacktracks && (s.descent || result.iterations < s.max_iterations);
           ++attempt, alpha *= 0.5) {
        stop_if_asked();
        trial_y = y + alpha * delta;
        trial_fit = point.fit;  // its rotations start the fit
        const double trial_energy = problem.local_fit(trial_y, trial_fit);
        if (!std::isfinite(trial_energy)) continue;
        bool keep = false;
        if (s.descent) {
          keep = trial_energy <= point.energy + kArmijo * alpha * slope;
        } else {
          const double trial_r = evaluate(trial_y, trial_fit, trial_rhs, trial_g);
          keep = std::isfinite(trial_r) && (trial_rhs - problem.A() * trial_y).norm() <= (1.0 - kArmijo * alpha) * b_norm;
          result.energies.push_back(keep ? trial_energy : point.energy);
        }
        if (keep) {
          y.swap(trial_y);
          std::swap(point.fit, trial_fit);
          point.energy = trial_energy;
          if (s.descent) {
            result.energies.back() = point.energy;
          } else {
            g.swap(trial_g);
            rhs.swap(trial_rhs);
            have_g = true;
          }
          accepted = true;
          break;
        }
      }
    }
    if (tracing())
      std::fprintf(stderr, "newton %d%s: r %.2e |b| %.2e shift %.3g eta %.3g krylov %d (%.1e) step %.2e alpha %.3g %s E %.10g\n",
                   result.newton_steps, positive_model ? " (model)" : "", r, b_norm, step_shift, eta, krylov.iterations, krylov.relative_residual,
                   step_size, alpha, accepted ? "kept" : "failed", point.energy);
    if (accepted && positive_model && alpha == 1.0 && step_size <= kModelToNewton * s.tolerance) near_minimum = true;
    if (accepted) {
      last_exact_step = exact && alpha == 1.0 ? step_size : std::numeric_limits<double>::infinity();
      if (exact) result.distance_estimate = step_size;
      // lambda < 1: the kept trial's own residual must agree.
      if (final_step && alpha == 1.0 && (s.descent || result.residuals.back() <= s.tolerance)) {
        result.converged = true;
        return;
      }
      shift = alpha == 1.0 ? (shift < kShiftFloor ? 0.0 : shift / kShiftRelax) : std::max(shift * kShiftRaise, 10.0 * kShiftFloor);
    } else {
      ++result.line_search_failures;
      plain_left = kFallbackSteps;
      last_exact_step = std::numeric_limits<double>::infinity();
      shift = std::max(shift * kShiftRaise * kShiftRaise, 1.0);
      point.energy = problem.local_fit(y, point.fit);  // the trials moved the linearization point
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
