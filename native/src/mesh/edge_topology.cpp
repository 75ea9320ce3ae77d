#include "mesh/edge_topology.h"

#include <algorithm>
#include <vector>

#include "base/bucket_order.h"

namespace edgedeform {

EdgeTopology build_edge_topology(const RowMatrixX3i& F, int n_vertices) {
  const Eigen::Index m = F.rows();
  // Corner 3 f + k of face f names the edge opposite it, (a, b) with a < b. The corners are
  // grouped by a (a counting sort), then each group by (b, corner): the edges come out in
  // lexicographic order, the corners of one edge together.
  const auto n_corners = static_cast<size_t>(3 * m);
  std::vector<int> low(n_corners), high(n_corners);
  for (Eigen::Index f = 0; f < m; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, (k + 1) % 3), b = F(f, (k + 2) % 3);
      low[static_cast<size_t>(3 * f + k)] = std::min(a, b);
      high[static_cast<size_t>(3 * f + k)] = std::max(a, b);
    }
  Buckets by_low = bucket_order(low, n_vertices);
  for (int v = 0; v < n_vertices; ++v)
    std::sort(by_low.order.begin() + by_low.offsets[static_cast<size_t>(v)],
              by_low.order.begin() + by_low.offsets[static_cast<size_t>(v) + 1], [&](int x, int y) {
                return high[static_cast<size_t>(x)] != high[static_cast<size_t>(y)]
                           ? high[static_cast<size_t>(x)] < high[static_cast<size_t>(y)]
                           : x < y;
              });
  const std::vector<int>& corners = by_low.order;

  EdgeTopology topo;
  topo.face_edges.resize(m, 3);
  std::vector<int> a_list, b_list, counts;
  for (size_t s = 0; s < corners.size();) {
    const auto first = static_cast<size_t>(corners[s]);
    size_t e = s;
    while (e < corners.size() && low[static_cast<size_t>(corners[e])] == low[first] &&
           high[static_cast<size_t>(corners[e])] == high[first])
      ++e;
    const int edge = static_cast<int>(a_list.size());
    for (size_t c = s; c < e; ++c) topo.face_edges(corners[c] / 3, corners[c] % 3) = edge;
    a_list.push_back(low[first]);
    b_list.push_back(high[first]);
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
