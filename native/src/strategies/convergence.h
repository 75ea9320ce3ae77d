// How far the iteration's output is from its fixed point, as a fraction of the rest
// bounding-box diagonal (docs/design.md §4).
//
// For a map G that contracts with factor rho near its fixed point x*, any point y satisfies
//     |G(y) - x*| = |G(y) - G(x*)| <= rho |y - x*| <= rho (|y - G(y)| + |G(y) - x*|),
// so the plain step g = G(y) lies within rho/(1-rho) times the residual |g - y| of x*. rho is
// not known; it is estimated from secant ratios |G(y_k) - G(y_{k-1})| / |y_k - y_{k-1}| of
// consecutive iterates (for the plain method these are the ratios of successive residuals),
// taking the largest of the recent ones, so that a slow mode seen lately is not forgotten.
#pragma once

#include <algorithm>
#include <array>
#include <limits>

#include <Eigen/Core>

namespace edgedeform {

// max over rows of |A_r - B_r| (Euclidean per vertex).
double max_row_distance(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B);

class ConvergenceMonitor {
 public:
  // Recent secant ratios kept; the rate is their largest. The accelerated iterates' ratios
  // see the slow mode only now and then, so a short memory forgets it: with 8 the 50k
  // koala lift (edge) claimed converged 4.1e-3 diag away (lambda 1, 471 iterations) and
  // 3.4e-3 away (lambda 0.5, 601 iterations); with 32, 5.6e-5 (766) and 9.0e-4 (884).
  // Cost: on the small samples up to 2x more iterations before the claim (dino).
  static constexpr int kWindow = 32;
  // Needed before any estimate. Right after a target change the first ratios see only the
  // fast modes near the handles (measured: a stopped drag on Spot, edge, claimed 1e-3 from
  // 2 ratios while 9e-3 diag away).
  static constexpr int kMinRatios = 8;
  // A residual this small (fraction of diag) is round-off: the point is a fixed point to
  // working precision, whatever the rate (measured: residuals wander between 3e-11 and
  // 2e-10 at the dino's rigidly moved rest shape, primal, lambda 0, where L^T L squares the
  // conditioning; elsewhere 1e-15..1e-12).
  static constexpr double kRoundoff = 1e-9;
  // Below this residual the secant ratios can be ratios of noise: the accelerated iteration
  // at lambda < 1 sits at a floor of 2e-8..6e-8 on the head sample (edge) and the 50k koala
  // lift, where they came out >= 1 and the solve never claimed convergence although its
  // residual stayed near 1e-8 from iteration 200 on. There, when the ratios give no rate,
  // the estimate assumes the slowest contraction ever measured with margin, kSlowestRate
  // (the koala's smooth mode: 0.998-0.999), so 1e-7 counts as at most 1e-3 diag away.
  static constexpr double kNoiseFloor = 1e-7;
  static constexpr double kSlowestRate = 0.9999;

  void resize(Eigen::Index rows);  // allocates the two copies; forgets everything
  void reset() { has_last_ = false; count_ = 0; next_ = 0; rate_floor_ = 0.0; }
  // Until the next reset, the rate is at least `rho` (a claim check's estimate of J_G's
  // largest modulus, claim_check.h), whatever the secant ratios say.
  void raise_rate(double rho) { rate_floor_ = std::max(rate_floor_, rho); }

  // Records y and g, which is G(y) when `is_map_pair` (false for the first step of a cold
  // start, which solves with rotations that were not fitted to y).
  void add(const Eigen::MatrixXd& y, const Eigen::MatrixXd& g, bool is_map_pair);

  // Largest recent secant ratio, or infinity while fewer than kMinRatios are known.
  double rate() const;
  // Estimated |G(y) - x*| / diag given the residual |G(y) - y| / diag of the last pair.
  double distance(double residual) const;

 private:
  Eigen::MatrixXd last_y_, last_g_;
  std::array<double, kWindow> ratios_{};
  int count_ = 0, next_ = 0;
  double rate_floor_ = 0.0;
  bool has_last_ = false;
};

}  // namespace edgedeform
