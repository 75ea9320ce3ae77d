#include "system/operator_cache.h"

#include <utility>

#include "system/system_restriction.h"

namespace edgedeform {

std::shared_ptr<const ConstrainedSystem> OperatorCache::set_system(ConstrainedSystem layout) {
  auto system = std::make_shared<ConstrainedSystem>(std::move(layout));
  const bool within_base = base_system_ && frees_subset(*system, *base_system_);
  if (within_base) return system;
  add_jacobians(*system);
  make_base(system);
  return system;
}

void OperatorCache::make_base(std::shared_ptr<const ConstrainedSystem> whole) {
  base_system_ = std::move(whole);
  base_assembled_.reset();
}

std::shared_ptr<const AssembledSystem> OperatorCache::operators_for(const ConstrainedSystem& system,
                                                                    const Eigen::VectorXd& vertex_lambda) {
  // system frees a subset of the base's vertices (set_system).
  if (!restriction_keeps_pattern(*base_system_, system, vertex_lambda)) {
    // Lambda = 1 on every term of this set but not of the base: this set becomes the base.
    auto whole = std::make_shared<ConstrainedSystem>(system);
    add_jacobians(*whole);
    make_base(std::move(whole));
  }
  if (!base_assembled_) {
    ++base_values_;
    base_assembled_ = std::make_shared<AssembledSystem>(assemble_system(*base_system_, vertex_lambda));
    ++assemblies_;
  } else if (!assembled_at(*base_assembled_, *base_system_, vertex_lambda)) {
    // Only lambda changed: new values in the same operators. Held apart meanwhile, so that
    // a failure leaves no half-updated base (the next call assembles anew).
    ++base_values_;
    std::shared_ptr<AssembledSystem> base = std::move(base_assembled_);
    update_stiffness(*base, *base_system_, vertex_lambda);
    base_assembled_ = std::move(base);
  }
  if (system.n_free() == base_system_->n_free()) return base_assembled_;  // the same free vertices
  return std::make_shared<AssembledSystem>(restrict_assembly(*base_assembled_, *base_system_, system, vertex_lambda));
}

}  // namespace edgedeform
