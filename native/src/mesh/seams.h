// Unwelded seams: vertices that share one position but are separate vertices (a mesh split
// along UV seams or exported per part). The solver moves each copy on its own, so a seam can
// tear open; the Deformer warns when it does (the Python package can weld them instead).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "base/types.h"

namespace edgedeform {

struct SeamCopies {
  // Each group: two or more face-referenced vertices with bit-identical positions.
  std::vector<std::vector<int>> groups;
  std::vector<int> piece;  // connected piece of every vertex (see connected_pieces)
};

SeamCopies find_seam_copies(const RowMatrixX3d& V, const RowMatrixX3i& F);

// A warning naming how many coincident vertices ended more than `tolerance` apart from a copy
// of theirs, and in how many connected pieces they lie; nullopt when none did.
std::optional<std::string> seam_warning(const SeamCopies& seams, const RowMatrixX3d& X, double tolerance);

}  // namespace edgedeform
