// A region of interest picked by distance from seed vertices, as Blender's proportional
// editing picks the vertices it moves: straight-line distance, or ("Connected Only") the
// shortest path along the mesh edges, which reaches only the seeds' own components.
#pragma once

#include <vector>

#include "base/types.h"
#include "mesh/mesh_incidence.h"

namespace edgedeform {

// Vertices v (ascending ids) with distance(v, seeds) <= radius, measured in V (#V x 3):
// Euclidean |V(v) - V(s)| (compared squared), or with `over_surface` the distance over the
// mesh (`neighbours`) as Blender's Connected Only measures it: along the edges and straight
// across the faces (unfolded, as fast marching does), so on a flat mesh it is the Euclidean
// distance, and parts that are near in space but not joined stay out. The seeds are inside (0).
// Throws std::invalid_argument unless radius is finite and > 0, std::out_of_range for a seed
// that is not a vertex.
std::vector<int> vertices_within_distance(const RowMatrixX3d& V, const VertexNeighbours& neighbours,
                                          const std::vector<int>& seeds, double radius, bool over_surface);

}  // namespace edgedeform
