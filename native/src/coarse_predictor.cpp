#include "edgedeform/coarse_predictor.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include "edgedeform/convergence.h"
#include "edgedeform/deformer.h"
#include "edgedeform/errors.h"

namespace edgedeform {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) { return std::chrono::duration<double, std::milli>(Clock::now() - start).count(); }
// |A (G(x) - x)| at x (fitted as `fit`): one global step, counted as an iteration.
double evaluate_merit(FixedPointProblem& problem, const Eigen::MatrixXd& x, const LocalFit& fit, double energy, double diag,
                      PredictorOutcome& out, SolveResult& result) {
  Eigen::MatrixXd rhs, g;
  problem.global_step(fit, rhs, g);
  ++result.iterations;
  ++out.evaluations;
  const double r = max_row_distance(g, x) / diag;
  result.residuals.push_back(r);
  result.energies.push_back(energy);
  const double merit = (rhs - problem.A() * x).norm();
  return std::isfinite(r) && std::isfinite(merit) ? merit : std::numeric_limits<double>::infinity();
}

}  // namespace

PredictorOutcome coarse_predict(FixedPointProblem& problem, const CoarseBasis& basis, const SparseMatrix& coarse_stiffness,
                                PredictorMemory& memory, double diag, Eigen::MatrixXd& y, LocalFit& fit,
                                double& energy, SolveResult& result) {
  PredictorOutcome out;
  // Ctrl-C answers here too (before y moves: the caller's iterate stays as it was).
  const auto stop_if_asked = [&] {
    if (problem.interrupt_requested()) throw SolveInterrupted("solve interrupted");
  };
  stop_if_asked();
  // The plain step exactly as a warm solve without predictor takes it: from the warm fit
  // (fitted where the handles were), so that a rejected prediction changes nothing.
  Eigen::MatrixXd rhs, g;
  problem.global_step(fit, rhs, g);
  ++result.iterations;
  ++out.evaluations;
  const double residual = max_row_distance(g, y) / diag;
  result.residuals.push_back(residual);
  result.energies.push_back(energy);
  const Eigen::MatrixXd b = rhs - problem.A() * y;

  // The linearization at y with the handles where they are now.
  Eigen::MatrixXd prediction;
  if (std::isfinite(residual)) {
    LocalFit here = fit;
    problem.local_fit(y, here);
    const std::unique_ptr<FixedPointLinearization> lin = problem.linearize(here, false);
    const auto t0 = Clock::now();
    if (!memory.correction.ready() || ++memory.age >= kPredictorLag) {
      memory.age = 0;
      if (memory.correction.factor(basis, coarse_operator(basis, coarse_stiffness, *lin))) ++result.coarse_factorizations;
    }
    result.coarse_ms += ms_since(t0);
    stop_if_asked();  // the assembly can take a second at 140k
    if (memory.correction.ready()) {
      Eigen::MatrixXd coarse_part, product, fine;
      memory.correction.apply(b, coarse_part);
      lin->newton_operator(coarse_part, product);
      problem.solve_A(b - product, fine);
      prediction = y + coarse_part + fine;
    }
  }
  // Safeguard: the prediction must lower |A (G(x) - x)| below the start's. Not below the
  // plain step's: that merit is dominated by the stiff, high-frequency part, which one plain
  // step removes and the patches' seams leave, and it cannot see the soft modes the
  // prediction carries (measured on the dino's lift drag at lambda 0.5, 30 ticks of 4
  // iterations: predictions with 3-10x the plain step's |A F| ended the drag 2.4e-3 of the
  // diagonal from the fixed point, against 2.9e-2 without them). On a flat grid's bend,
  // where the plain step is exact at once, the predictions' |A F| is 3x the start's.
  if (prediction.size() != 0) {
    LocalFit trial_fit = fit;  // its rotations start the fit
    const double trial_energy = problem.local_fit(prediction, trial_fit);
    const double trial_merit = evaluate_merit(problem, prediction, trial_fit, trial_energy, diag, out, result);
    if (trial_merit < b.norm()) {
      y.swap(prediction);
      fit = std::move(trial_fit);
      energy = trial_energy;
      out.kept = true;
      return out;
    }
  }
  // Rejected (or no coarse factor): the plain step from the warm fit, as without predictor.
  y.swap(g);
  energy = problem.local_fit(y, fit);
  return out;
}

}  // namespace edgedeform
