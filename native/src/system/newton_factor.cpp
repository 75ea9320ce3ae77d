#include "edgedeform/newton_factor.h"

#include <chrono>

#include "edgedeform/errors.h"

namespace edgedeform {

namespace {
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}
}  // namespace

bool NewtonFactor::factor(const FixedPointLinearization& lin) {
  auto t0 = Clock::now();
  if (!matrix_) {
    matrix_ = std::make_unique<NewtonMatrix>(lin.system(), lin.assembled());
    // Order the vertices (nf x nf, a ninth of the entries) and keep each vertex's three
    // coordinates together: the factor's supernodes then hold whole 3 x 3 blocks.
    order_ = NewtonMatrix::coordinate_order(SparseCholesky::fill_reducing_order(matrix_->block_pattern()));
  }
  matrix_->assemble(lin);
  assemble_ms_ = ms_since(t0);
  t0 = Clock::now();
  bool ok = true;
  try {
    cholesky_.factorize(matrix_->transpose(), order_);  // K^T = K
  } catch (const FactorizationError&) {
    ok = false;
  }
  factor_ms_ = ms_since(t0);
  return ok;
}

void NewtonFactor::solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& delta) {
  const Eigen::Index nf = b.rows();
  Eigen::VectorXd rhs(3 * nf);  // row 3 v + c: coordinate c of free vertex v (newton_matrix.h)
  for (Eigen::Index v = 0; v < nf; ++v)
    for (int c = 0; c < 3; ++c) rhs(3 * v + c) = b(v, c);
  Eigen::MatrixXd x;
  cholesky_.solve(rhs, x);
  delta.resize(nf, 3);
  for (Eigen::Index v = 0; v < nf; ++v)
    for (int c = 0; c < 3; ++c) delta(v, c) = x(3 * v + c, 0);
}

}  // namespace edgedeform
