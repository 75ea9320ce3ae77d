// Quality of a deformed mesh against its rest shape.
#pragma once

#include <vector>

#include "base/types.h"

namespace edgedeform {

struct QualityMetrics {
  double handle_error = 0.0;          // max |x_h - target|
  double mean_edge_strain = 0.0;      // |l - l0| / l0 over mesh edges
  double max_edge_strain = 0.0;
  // mean |theta - theta0| (radians) over every pair of faces at an edge (one pair at an
  // interior edge, three at a fin's edge)
  double mean_dihedral_change = 0.0;
  double arap_energy = 0.0;           // classic primal ARAP (clamped cotangent spokes)
  double arap_energy_normalized = 0.0;  // arap_energy / sum_ij w_ij |e0_ij|^2
};

// `handles` and `targets` may be empty. Throws like check_mesh for bad input.
QualityMetrics compute_metrics(const RowMatrixX3d& rest, const RowMatrixX3i& F,
                               const RowMatrixX3d& deformed, const std::vector<int>& handles,
                               const RowMatrixX3d& targets);

}  // namespace edgedeform
