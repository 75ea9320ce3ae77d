// Which vertices share a mesh edge with which: the graph walks over the surface (components
// that touch no constraint, regions picked along the edges) run on it. The Deformer builds
// it once per mesh, so that a set_constraints on a large mesh does not rebuild it.
#pragma once

#include <vector>

#include "edgedeform/types.h"

namespace edgedeform {

// Compressed rows: the neighbours of v are neighbours[offsets[v] .. offsets[v + 1]), in the
// order of the edges it was built from.
struct VertexAdjacency {
  std::vector<int> offsets{0};
  std::vector<int> neighbours;

  int n_vertices() const { return static_cast<int>(offsets.size()) - 1; }
};

// Over `n` vertices from `edges` (#E x 2, vertex ids < n).
VertexAdjacency vertex_adjacency(const RowMatrixX2i& edges, int n);

}  // namespace edgedeform
