#include "strategies/anderson.h"

#include <algorithm>
#include <cmath>

namespace edgedeform {

namespace {
// Tikhonov term relative to the (unit) diagonal of the normalised Gram matrix: keeps the
// least squares solvable when two residual differences are nearly parallel, and is far
// below the size of any difference that matters.
constexpr double kRegularization = 1e-10;
}  // namespace

void AndersonAccelerator::resize(Eigen::Index dimension, int window) {
  const int m = std::max(window, 1);
  if (dF_.rows() != dimension || dF_.cols() != m) {
    dF_.resize(dimension, m);
    dG_.resize(dimension, m);
    last_f_.resize(dimension);
    last_g_.resize(dimension);
    normal_.resize(m, m);
    rhs_.resize(m);
    theta_.resize(m);
    scratch_.resize(dimension);
  }
  reset();
}

bool AndersonAccelerator::step(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& g,
                               Eigen::Ref<Eigen::VectorXd> out) {
  // f = g - x, kept in scratch_ until it becomes last_f_.
  scratch_ = g - x;
  if (has_last_) {
    // The newest difference replaces the oldest; normalising by |df| keeps the Gram matrix
    // well scaled however small the residuals get (Peng et al.'s implementation does the same).
    const double norm = (scratch_ - last_f_).norm();
    if (norm > 0.0) {
      dF_.col(next_) = (scratch_ - last_f_) / norm;
      dG_.col(next_) = (g - last_g_) / norm;
      next_ = (next_ + 1) % window();
      stored_ = std::min(stored_ + 1, window());
    }
  }
  last_f_ = scratch_;
  last_g_ = g;
  has_last_ = true;
  if (stored_ == 0) {
    out = g;
    return false;
  }
  // theta = argmin |f - dF theta|^2 + mu |theta|^2; then out = g - dG theta.
  const int m = stored_;
  auto F = dF_.leftCols(m);
  normal_.topLeftCorner(m, m).noalias() = F.transpose() * F;
  normal_.topLeftCorner(m, m).diagonal().array() += kRegularization;
  rhs_.head(m).noalias() = F.transpose() * last_f_;
  ldlt_.compute(normal_.topLeftCorner(m, m));
  theta_.head(m) = ldlt_.solve(rhs_.head(m));
  if (!theta_.head(m).allFinite()) {
    out = g;
    return false;
  }
  out = g;
  out.noalias() -= dG_.leftCols(m) * theta_.head(m);
  return true;
}

}  // namespace edgedeform
