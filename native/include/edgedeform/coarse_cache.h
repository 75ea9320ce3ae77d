// The Deformer's coarse space (coarse_space.h), one owner for its state: the basis of the
// current constraint set (per patch count and blend), U^T A U of the current operators,
// the Newton preconditioner's factored correction and the live predictor's lagged one.
// The basis goes stale when the constraints change, U^T A U and the predictor's factor
// when the operators do (a new stiffness).
#pragma once

#include <memory>

#include "edgedeform/coarse_predictor.h"
#include "edgedeform/coarse_space.h"

namespace edgedeform {

class CoarseCache {
 public:
  // The basis for (patches, blend) over `system`'s free vertices, built on first use;
  // null when there is none (patches = 0, or too few free vertices).
  const CoarseBasis* basis(const ConstrainedSystem& system, const RowMatrixX3d& rest, const RowMatrixX2i& mesh_edges,
                           int patches, int blend);
  // U^T A U of the basis last returned by basis() (which must not be null).
  const SparseMatrix& stiffness(const SparseMatrix& A);
  // Kept between solves: the symbolic analyses last as long as the basis.
  CoarseCorrection& newton_correction() { return newton_correction_; }
  PredictorMemory& predictor() { return predictor_; }

  void constraints_changed();  // a new constraint set: everything goes
  void operators_changed();    // a new A: U^T A U and the predictor's lagged factor go

 private:
  std::shared_ptr<const CoarseBasis> basis_;
  int patches_ = -1, blend_ = -1;
  SparseMatrix stiffness_;
  bool stiffness_valid_ = false;
  CoarseCorrection newton_correction_;
  PredictorMemory predictor_;
};

}  // namespace edgedeform
