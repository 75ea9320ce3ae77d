// The Cholesky factors of A for the constraint sets in use, made as rarely as possible:
// analysis (ordering, symbolic factorization), numeric factorization, back-substitution.
//
// Two factors are kept, swapped as sets change. While a part of the base set is factored (a
// handle group pinned: operator_cache.h), the other keeps the base set's, so that releasing
// the group costs no factorization, and pinning the same group again finds its analysis
// there. A factor is the base's while its tag equals the operator cache's base_values(),
// which counts every new value of the base's operators; -1 for a part's factor.
//
// Fill-reducing orders are remembered per vertex, one per pattern of A, so that a set freeing
// only vertices an earlier set freed is analyzed without a new ordering (free_vertex_order).
#pragma once

#include <vector>

#include "system/constrained_system.h"
#include "linear_algebra/sparse_cholesky.h"

namespace edgedeform {

class FactorCache {
 public:
  // The factor of `assembled` (the operators of `system`, n_free() > 0): kept, swapped back,
  // or factored now (throws FactorizationError). `is_base` and `base_values` come from the
  // OperatorCache that made `assembled`.
  SparseCholesky& factor_for(const ConstrainedSystem& system, const AssembledSystem& assembled, bool is_base,
                             long base_values);
  // The factor of the last factor_for call.
  SparseCholesky& factor() { return cholesky_; }

  int analyses() const { return cholesky_.analyses() + spare_cholesky_.analyses(); }
  int orderings() const { return cholesky_.orderings() + spare_cholesky_.orderings(); }
  int factorizations() const { return cholesky_.factorizations() + spare_cholesky_.factorizations(); }
  double factor_nonzeros() const { return cholesky_.factor_nonzeros(); }

 private:
  // Factors A into cholesky_ (ordering as vertex_rank_ allows).
  void factorize(const ConstrainedSystem& system, const AssembledSystem& assembled);
  void swap_factors();
  // Keeps the elimination order CHOLMOD chose for system's free vertices and pattern.
  void remember_order(const ConstrainedSystem& system, bool laplacian_pattern);

  // Elimination rank per vertex (-1: never free) from the last fill-reducing ordering, one
  // per pattern of A: [0] lambda = 1 everywhere, [1] with the Laplacian term (some lambda
  // < 1). The other pattern's order fills badly (koala, edge domain: the lambda = 1 order on
  // the lambda = 0.5 pattern gave 4.9x the factor entries, and every back-substitution 2.7x
  // the time), so the slider crossing 1 orders each pattern once and then reuses its order.
  std::vector<int> vertex_rank_[2];
  SparseCholesky cholesky_, spare_cholesky_;
  long cholesky_tag_ = -1, spare_tag_ = -1;
};

}  // namespace edgedeform
