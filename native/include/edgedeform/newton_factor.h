// The Newton matrix of the current operators, assembled and factored for direct Newton steps
// (docs/design.md §4, "Reaching the fixed point"): its pattern and fill-reducing order made
// once per set of operators, the numeric factorization at every step: CHOLMOD's supernodal
// LL^T (Newton steps are taken where lambda = 1 on every term, where K is the energy's
// Hessian: docs/decisions/0029).
#pragma once

#include <memory>
#include <vector>

#include "edgedeform/fixed_point_linearization.h"
#include "edgedeform/newton_matrix.h"
#include "edgedeform/sparse_cholesky.h"

namespace edgedeform {

class NewtonFactor {
 public:
  // The operators changed (constraints or stiffness): the next factor() makes the pattern anew.
  void operators_changed() { matrix_.reset(); }

  // Assembles K at `lin` and factors it: LL^T, false when K is not positive definite. The
  // pattern is made on the first call after operators_changed(); `lin` must be of the
  // operators of that first call.
  bool factor(const FixedPointLinearization& lin);
  // delta := K^-1 b, b and delta (#free x 3) as the strategies hold them.
  void solve(const Eigen::MatrixXd& b, Eigen::MatrixXd& delta);

  // Milliseconds of the last factor(): assembling K (pattern included when new), factoring.
  double assemble_ms() const { return assemble_ms_; }
  double factor_ms() const { return factor_ms_; }

 private:
  std::unique_ptr<NewtonMatrix> matrix_;
  std::vector<int> order_;  // per coordinate, from a fill-reducing order of the vertices
  SparseCholesky cholesky_;
  double assemble_ms_ = 0.0, factor_ms_ = 0.0;
};

}  // namespace edgedeform
