// Sparse Cholesky of a symmetric positive definite matrix: CHOLMOD supernodal LL^T, or
// Eigen's SimplicialLDLT in a build without CHOLMOD. The symbolic analysis is kept while the
// sparsity pattern stays the same, so a change of stiffness only refactors numerically.
#pragma once

#include <memory>

#include "edgedeform/types.h"

namespace edgedeform {

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Factors A (square, compressed; only the lower triangle is read). Re-analyzes only when
  // the pattern differs from the last call. Throws FactorizationError if A is not positive
  // definite; the object is then empty until the next successful factorize.
  void factorize(const SparseMatrix& A);
  // Solves A X = B for a factored A. B and X are (n x k), column-major.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);

  bool factored() const;
  int analyses() const;  // how many symbolic analyses so far (tests check reuse)
  static const char* backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace edgedeform
