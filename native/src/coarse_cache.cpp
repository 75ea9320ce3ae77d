#include "edgedeform/coarse_cache.h"

namespace edgedeform {

const CoarseBasis* CoarseCache::basis(const ConstrainedSystem& system, const RowMatrixX3d& rest,
                                      const RowMatrixX2i& mesh_edges, int patches, int blend) {
  if (patches <= 0) return nullptr;
  if (!basis_ || patches_ != patches || blend_ != blend) {
    constraints_changed();
    basis_ = std::make_shared<const CoarseBasis>(build_coarse_basis(system, rest, mesh_edges, patches, blend));
    patches_ = patches;
    blend_ = blend;
  }
  return basis_->dimension() > 0 ? basis_.get() : nullptr;
}

const SparseMatrix& CoarseCache::stiffness(const SparseMatrix& A) {
  if (!stiffness_valid_) {
    stiffness_ = coarse_stiffness(*basis_, A);
    stiffness_valid_ = true;
  }
  return stiffness_;
}

void CoarseCache::constraints_changed() {
  basis_.reset();
  patches_ = blend_ = -1;
  newton_correction_ = CoarseCorrection();
  operators_changed();
}

void CoarseCache::operators_changed() {
  stiffness_valid_ = false;
  predictor_.forget();
}

}  // namespace edgedeform
