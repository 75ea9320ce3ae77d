// Unique undirected edges of a triangle mesh, and which edge lies opposite each corner.
#pragma once

#include "base/types.h"

namespace edgedeform {

struct EdgeTopology {
  RowMatrixX2i edges;        // #E x 2, a < b, sorted lexicographically
  RowMatrixX3i face_edges;   // #F x 3, face_edges(f,k) = edge opposite corner k of face f
  // #E, faces sharing each edge: 1 = boundary, 2 = interior, k > 2 = non-manifold (a fin,
  // sheets meeting at a T-junction); every count is valid input.
  Eigen::VectorXi face_count;
};

EdgeTopology build_edge_topology(const RowMatrixX3i& F, int n_vertices);

}  // namespace edgedeform
