#include "system/factor_cache.h"

#include <utility>

namespace edgedeform {

SparseCholesky& FactorCache::factor_for(const ConstrainedSystem& system, const AssembledSystem& assembled,
                                        bool is_base, long base_values) {
  if (is_base && spare_tag_ == base_values) swap_factors();  // a group released again
  if (!(is_base && cholesky_tag_ == base_values)) {
    if (!is_base && cholesky_tag_ == base_values) swap_factors();  // keep the base's aside
    cholesky_tag_ = -1;  // until factored
    factorize(system, assembled);  // throws FactorizationError
    cholesky_tag_ = is_base ? base_values : -1;
  }
  return cholesky_;
}

void FactorCache::factorize(const ConstrainedSystem& system, const AssembledSystem& assembled) {
  const bool laplacian_pattern = assembled.laplacian_term;  // A's pattern (update_stiffness)
  const std::vector<int>& rank = vertex_rank_[laplacian_pattern];
  const std::vector<int> order = free_vertex_order(system, rank);  // empty if some vertex is unranked
  if (!order.empty()) {
    cholesky_.factorize(assembled.A, order);
    return;
  }
  // Lambda moved to or from 1 everywhere for the first time (only the other pattern has an
  // order): a quick order, as this is the live slider; otherwise the least fill.
  const bool crossing = rank.empty() && !vertex_rank_[!laplacian_pattern].empty();
  cholesky_.factorize(assembled.A, crossing ? Ordering::Quick : Ordering::LeastFill);
  remember_order(system, laplacian_pattern);
}

void FactorCache::swap_factors() {
  cholesky_.swap(spare_cholesky_);
  std::swap(cholesky_tag_, spare_tag_);
}

void FactorCache::remember_order(const ConstrainedSystem& system, bool laplacian_pattern) {
  const std::vector<int> order = cholesky_.order();
  std::vector<int>& vertex_rank = vertex_rank_[laplacian_pattern];
  vertex_rank.assign(static_cast<size_t>(system.n_vertices), -1);
  for (size_t k = 0; k < order.size(); ++k)
    vertex_rank[static_cast<size_t>(system.free_vertices[static_cast<size_t>(order[k])])] = static_cast<int>(k);
}

}  // namespace edgedeform
