#include "mesh/mesh_incidence.h"

#include <algorithm>
#include <utility>

#include "base/bucket_order.h"

namespace edgedeform {

void VertexNeighbours::sorted(int v, std::vector<int>& out) const {
  out.clear();
  for_each(v, [&](int u) { out.push_back(u); });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

int VertexNeighbours::edge_id(int a, int b) const {
  if (a > b) std::swap(a, b);
  std::vector<int> ring;
  sorted(a, ring);
  const auto above = std::upper_bound(ring.begin(), ring.end(), a);
  const auto it = std::lower_bound(above, ring.end(), b);
  if (it == ring.end() || *it != b) return -1;
  return m_.edge_offsets[static_cast<size_t>(a)] + static_cast<int>(it - above);
}

MeshIncidence mesh_incidence(const RowMatrixX3i& F, int n) {
  MeshIncidence m;
  // Corners grouped by their vertex; within a vertex in ascending corner, so ascending face.
  std::vector<int> corner_vertex(static_cast<size_t>(3 * F.rows()));
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) corner_vertex[static_cast<size_t>(3 * f + k)] = F(f, k);
  Buckets by_vertex = bucket_order(corner_vertex, n);
  std::vector<int>().swap(corner_vertex);
  m.face_offsets = std::move(by_vertex.offsets);
  m.faces = std::move(by_vertex.order);
  for (int& corner : m.faces) corner /= 3;

  // Each edge counted once, at its lower vertex: v's distinct neighbours above it.
  m.edge_offsets.assign(static_cast<size_t>(n) + 1, 0);
  std::vector<int> above;
  for (int v = 0; v < n; ++v) {
    above.clear();
    for (int s = m.face_offsets[static_cast<size_t>(v)]; s < m.face_offsets[static_cast<size_t>(v) + 1]; ++s)
      for (int k = 0; k < 3; ++k)
        if (F(m.faces[static_cast<size_t>(s)], k) > v) above.push_back(F(m.faces[static_cast<size_t>(s)], k));
    std::sort(above.begin(), above.end());
    const auto distinct = std::unique(above.begin(), above.end()) - above.begin();
    m.edge_offsets[static_cast<size_t>(v) + 1] = m.edge_offsets[static_cast<size_t>(v)] + static_cast<int>(distinct);
  }
  return m;
}

}  // namespace edgedeform
