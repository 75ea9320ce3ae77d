// Which vertices share a mesh edge with which: the graph walks over the surface (components
// that touch no constraint, regions picked along the edges) run on it.
#pragma once

#include <vector>

#include "edgedeform/types.h"

namespace edgedeform {

// Compressed rows over `n` vertices: the neighbours of v are adj[offsets[v] .. offsets[v + 1]),
// in the order of `edges` (#E x 2, vertex ids < n).
void vertex_adjacency(const RowMatrixX2i& edges, int n, std::vector<int>& offsets, std::vector<int>& adj);

}  // namespace edgedeform
