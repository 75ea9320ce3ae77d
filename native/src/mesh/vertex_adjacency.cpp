#include "edgedeform/vertex_adjacency.h"

namespace edgedeform {

VertexAdjacency vertex_adjacency(const RowMatrixX2i& edges, int n) {
  VertexAdjacency a;
  std::vector<int>& offsets = a.offsets;
  offsets.assign(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    ++offsets[static_cast<size_t>(edges(e, 0)) + 1];
    ++offsets[static_cast<size_t>(edges(e, 1)) + 1];
  }
  for (int v = 0; v < n; ++v) offsets[static_cast<size_t>(v) + 1] += offsets[static_cast<size_t>(v)];
  a.neighbours.resize(static_cast<size_t>(offsets.back()));
  std::vector<int> cursor(offsets.begin(), offsets.end() - 1);
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int u = edges(e, 0), v = edges(e, 1);
    a.neighbours[static_cast<size_t>(cursor[static_cast<size_t>(u)]++)] = v;
    a.neighbours[static_cast<size_t>(cursor[static_cast<size_t>(v)]++)] = u;
  }
  return a;
}

}  // namespace edgedeform
