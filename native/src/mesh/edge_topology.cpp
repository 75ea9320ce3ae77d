#include "edgedeform/edge_topology.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace edgedeform {

EdgeTopology build_edge_topology(const RowMatrixX3i& F, int n_vertices) {
  const Eigen::Index m = F.rows();
  // One (edge key, face corner) pair per corner; sorting groups the corners of each edge.
  std::vector<std::pair<int64_t, int>> corners(static_cast<size_t>(3 * m));
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      const int64_t key = static_cast<int64_t>(std::min(a, b)) * n_vertices + std::max(a, b);
      corners[static_cast<size_t>(3 * f + k)] = {key, static_cast<int>(3 * f + k)};
    }
  std::sort(corners.begin(), corners.end());

  EdgeTopology topo;
  topo.face_edges.resize(m, 3);
  std::vector<int> a_list, b_list, counts;
  for (size_t s = 0; s < corners.size();) {
    size_t e = s;
    while (e < corners.size() && corners[e].first == corners[s].first) ++e;
    const int64_t key = corners[s].first;
    const int a = static_cast<int>(key / n_vertices), b = static_cast<int>(key % n_vertices);
    const int edge = static_cast<int>(a_list.size());
    for (size_t c = s; c < e; ++c) topo.face_edges(corners[c].second / 3, corners[c].second % 3) = edge;
    a_list.push_back(a);
    b_list.push_back(b);
    counts.push_back(static_cast<int>(e - s));
    s = e;
  }
  const Eigen::Index ne = static_cast<Eigen::Index>(a_list.size());
  topo.edges.resize(ne, 2);
  topo.face_count.resize(ne);
  for (Eigen::Index e = 0; e < ne; ++e) {
    topo.edges(e, 0) = a_list[static_cast<size_t>(e)];
    topo.edges(e, 1) = b_list[static_cast<size_t>(e)];
    topo.face_count(e) = counts[static_cast<size_t>(e)];
  }
  return topo;
}

}  // namespace edgedeform
