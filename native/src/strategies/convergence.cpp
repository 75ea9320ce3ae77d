#include "strategies/convergence.h"

#include <algorithm>
#include <cmath>

namespace edgedeform {

double max_row_distance(const Eigen::Ref<const Eigen::MatrixXd>& A, const Eigen::Ref<const Eigen::MatrixXd>& B) {
  double m = 0.0;
  for (Eigen::Index r = 0; r < A.rows(); ++r) m = std::max(m, (A.row(r) - B.row(r)).squaredNorm());
  return std::sqrt(m);
}

void ConvergenceMonitor::resize(Eigen::Index rows) {
  last_y_.resize(rows, 3);
  last_g_.resize(rows, 3);
  reset();
}

void ConvergenceMonitor::add(const Eigen::MatrixXd& y, const Eigen::MatrixXd& g, bool is_map_pair) {
  if (!is_map_pair) {
    has_last_ = false;
    return;
  }
  if (has_last_) {
    const double dy = max_row_distance(y, last_y_);
    if (dy > 0.0) {
      ratios_[static_cast<size_t>(next_)] = max_row_distance(g, last_g_) / dy;
      next_ = (next_ + 1) % kWindow;
      count_ = std::min(count_ + 1, kWindow);
    }
  }
  last_y_ = y;
  last_g_ = g;
  has_last_ = true;
}

double ConvergenceMonitor::rate() const {
  if (count_ < kMinRatios) return std::numeric_limits<double>::infinity();
  return std::max(rate_floor_, *std::max_element(ratios_.begin(), ratios_.begin() + count_));
}

double ConvergenceMonitor::distance(double residual) const {
  if (residual <= kRoundoff) return residual;
  const double rho = rate();
  if (rho < 1.0) return residual * rho / (1.0 - rho);
  if (residual <= kNoiseFloor) return residual * kSlowestRate / (1.0 - kSlowestRate);  // ratios of noise
  return std::numeric_limits<double>::infinity();  // not (yet) seen to contract
}

}  // namespace edgedeform
