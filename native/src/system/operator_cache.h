// The constrained system's operators (A, K_fixed, H) for the current constraint set and
// stiffness, assembled as rarely as possible. The cache keeps a base set: the last set
// built whole (with J1, J2), and its operators once assembled, at the last stiffness asked
// for. A set freeing only vertices the base frees (a handle group added, a vertex pinned,
// the group released) is a layout without J1, J2 and takes its operators from the base's
// (system_restriction.h) instead of assembling its own.
//
// Invalidation: a set freeing a vertex the base does not becomes the base (its operators
// assembled on first use); a new stiffness updates the base's values in place (same
// pattern); a set whose restriction would carry the Laplacian's pattern the set does not
// have (lambda = 1 on all its terms, not on the base's) also becomes the base.
#pragma once

#include <memory>

#include "system/constrained_system.h"

namespace edgedeform {

class OperatorCache {
 public:
  // Takes a validated layout (constrained_layout) as the current set: within the base set's
  // free vertices it stays a layout, otherwise it gets J1, J2 and becomes the base. Returns
  // the set as kept. Changes nothing if it throws.
  std::shared_ptr<const ConstrainedSystem> set_system(ConstrainedSystem layout);

  // The operators of `system` (the set returned by the last set_system) at vertex_lambda
  // (#nodes): the base set's, or restricted from them. Throws like assemble_system.
  std::shared_ptr<const AssembledSystem> operators_for(const ConstrainedSystem& system,
                                                       const Eigen::VectorXd& vertex_lambda);

  // Whether `assembled` is the base set's operators (not a restriction).
  bool is_base(const std::shared_ptr<const AssembledSystem>& assembled) const {
    return assembled && assembled == base_assembled_;
  }
  // Counts every new value of the base's operators (an assembly, a stiffness change): a
  // factor of the base's A made at this count is still valid (factor_cache.h).
  long base_values() const { return base_values_; }
  // How many sets were assembled whole (sparse products); restrictions do not count.
  int assemblies() const { return assemblies_; }

 private:
  void make_base(std::shared_ptr<const ConstrainedSystem> whole);

  std::shared_ptr<const ConstrainedSystem> base_system_;
  std::shared_ptr<AssembledSystem> base_assembled_;  // null until first asked for
  long base_values_ = 0;
  int assemblies_ = 0;
};

}  // namespace edgedeform
