// Sparse LU of a square, nonsymmetric matrix whose pattern is symmetric: UMFPACK (its
// symmetric strategy, columns pre-ordered as given), or Eigen's SparseLU in a build without
// SuiteSparse. The symbolic analysis is kept while the pattern stays the same, so each new
// set of values only refactors numerically. The Newton matrix at lambda < 1 (newton_factor.h).
#pragma once

#include <memory>
#include <vector>

#include "edgedeform/types.h"

namespace edgedeform {

class SparseLU {
 public:
  SparseLU();
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  // Factors A (all entries read). `order` (order[k] = the column eliminated k-th; empty: the
  // library's own) is used when the pattern is new. Throws FactorizationError when A is
  // singular to working precision; the object is then empty until the next success.
  void factorize(const SparseMatrix& A, const std::vector<int>& order = {});
  // Solves A x = b (A^T x = b when `transposed`) for a factored A (b: one column of A's
  // size; std::invalid_argument otherwise, x untouched).
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, bool transposed = false);

  bool factored() const;
  int analyses() const;
  int factorizations() const;
  double factor_nonzeros() const;  // entries of L and U from the last factorization
  static const char* backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace edgedeform
