#include "strategies/claim_check.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "base/errors.h"

namespace edgedeform {

double largest_ritz_modulus(const std::function<void(const Eigen::MatrixXd&, Eigen::MatrixXd&)>& apply,
                            const Eigen::MatrixXd& start, int steps) {
  const double norm = start.norm();
  if (!(norm > 0.0) || steps < 1) return 0.0;
  std::vector<Eigen::MatrixXd> Q{start / norm};
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(steps + 1, steps);
  Eigen::MatrixXd w;
  int k = 0;
  while (k < steps) {
    apply(Q[static_cast<size_t>(k)], w);
    for (int pass = 0; pass < 2; ++pass)  // Gram-Schmidt twice: the basis stays orthogonal
      for (int i = 0; i <= k; ++i) {
        const double c = (Q[static_cast<size_t>(i)].array() * w.array()).sum();
        H(i, k) += c;
        w -= c * Q[static_cast<size_t>(i)];
      }
    H(k + 1, k) = w.norm();
    ++k;
    if (!(H(k, k - 1) > 1e-14 * norm)) break;  // an invariant subspace: its Ritz values are exact
    Q.push_back(w / H(k, k - 1));
  }
  const Eigen::VectorXcd ritz = Eigen::EigenSolver<Eigen::MatrixXd>(H.topLeftCorner(k, k), false).eigenvalues();
  double rho = 0.0;
  for (Eigen::Index i = 0; i < ritz.size(); ++i) rho = std::max(rho, std::abs(ritz(i)));
  return rho;
}

namespace {

// rho at free positions y with fit = fit(y) (the problem's last local_fit was at y),
// Krylov space started from `residual` (G(y) - y). Deterministic; asks the problem's
// interrupt between products.
double largest_jacobian_modulus(FixedPointProblem& problem, const LocalFit& fit, const Eigen::MatrixXd& residual) {
  const std::unique_ptr<FixedPointLinearization> lin = problem.linearize(fit);
  Eigen::MatrixXd d_rhs;
  const auto apply_J = [&](const Eigen::MatrixXd& q, Eigen::MatrixXd& out) {
    if (problem.interrupt_requested()) throw SolveInterrupted("solve interrupted");
    lin->rhs_derivative(q, d_rhs);
    problem.solve_A(d_rhs, out);  // J_G q = A^-1 D q
  };
  return largest_ritz_modulus(apply_J, residual, kClaimCheckSteps);
}

}  // namespace

double checked_distance(FixedPointProblem& problem, ConvergenceMonitor& monitor, const LocalFit& fit,
                        const Eigen::MatrixXd& y, const Eigen::MatrixXd& g, double r, bool map_pair,
                        bool verify_claims, double tolerance, SolveResult& result) {
  monitor.add(y, g, map_pair);
  if (!map_pair) return std::numeric_limits<double>::infinity();
  double distance = monitor.distance(r);
  if (verify_claims && distance < tolerance && r > ConvergenceMonitor::kRoundoff) {
    ++result.claim_checks;
    monitor.raise_rate(largest_jacobian_modulus(problem, fit, g - y));
    distance = monitor.distance(r);
    if (!(distance < tolerance)) ++result.refused_claims;
  }
  return distance;
}

}  // namespace edgedeform
