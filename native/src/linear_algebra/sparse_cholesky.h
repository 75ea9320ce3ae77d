// Sparse Cholesky of a symmetric positive definite matrix: CHOLMOD supernodal LL^T, or
// Eigen's SimplicialLDLT in a build without CHOLMOD. The symbolic analysis is kept while the
// sparsity pattern stays the same, so a change of stiffness only refactors numerically.
#pragma once

#include <memory>
#include <vector>

#include "base/types.h"

namespace edgedeform {

// How a new pattern is ordered when no elimination order is given.
enum class Ordering {
  LeastFill,  // AMD and METIS, keeping the one with less fill (METIS dominates the analysis)
  Quick,      // AMD alone: a fifth of the analysis; koala: 11 % (edge) to 15 % (primal) more fill
};

class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // Factors A (square, compressed; only the lower triangle is read). Re-analyzes only when
  // the pattern differs from the last call, ordering the new pattern as asked. Throws
  // FactorizationError if A is not positive definite; the object is then empty until the
  // next successful factorize.
  void factorize(const SparseMatrix& A, Ordering ordering = Ordering::LeastFill);
  // The same with a given elimination order (order[k] = the column eliminated k-th), so that
  // a new pattern costs only the symbolic factorization, not a new ordering (CHOLMOD; the
  // Eigen fallback orders by itself and ignores it).
  void factorize(const SparseMatrix& A, const std::vector<int>& order);
  // The elimination order of the current analysis (order[k] = column eliminated k-th);
  // empty before the first analysis and in the Eigen fallback.
  std::vector<int> order() const;
  // Solves A X = B for a factored A. B and X are (n x k), column-major, 1 <= k <= 16
  // (kMaxRightHandSides, supernodal_solve.h); std::invalid_argument otherwise, or when B's
  // rows are not A's, and X is then untouched.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);

  // Exchanges the factorizations (and their counts) of two solvers.
  void swap(SparseCholesky& other) noexcept { impl_.swap(other.impl_); }

  bool factored() const;
  int analyses() const;   // how many symbolic analyses so far (tests check reuse)
  int orderings() const;  // how many of them computed a fill-reducing order
  int factorizations() const;  // how many numeric factorizations so far
  double factor_nonzeros() const;  // entries of L from the last analysis (0 before any)
  // Whether solve() splits the factor's elimination tree into two halves of similar work
  // (supernodal_solve.h), run on two threads when there are two, in turn on one: the same
  // sums either way. Always false in the Eigen fallback.
  bool solves_in_parallel() const;
  static const char* backend();

 private:
  void factorize(const SparseMatrix& A, const std::vector<int>& order, Ordering ordering);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace edgedeform
