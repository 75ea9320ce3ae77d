#include "edgedeform/vertex_adjacency.h"

namespace edgedeform {

void vertex_adjacency(const RowMatrixX2i& edges, int n, std::vector<int>& offsets, std::vector<int>& adj) {
  offsets.assign(static_cast<size_t>(n) + 1, 0);
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    ++offsets[static_cast<size_t>(edges(e, 0)) + 1];
    ++offsets[static_cast<size_t>(edges(e, 1)) + 1];
  }
  for (int v = 0; v < n; ++v) offsets[static_cast<size_t>(v) + 1] += offsets[static_cast<size_t>(v)];
  adj.resize(static_cast<size_t>(offsets.back()));
  std::vector<int> cursor(offsets.begin(), offsets.end() - 1);
  for (Eigen::Index e = 0; e < edges.rows(); ++e) {
    const int a = edges(e, 0), b = edges(e, 1);
    adj[static_cast<size_t>(cursor[static_cast<size_t>(a)]++)] = b;
    adj[static_cast<size_t>(cursor[static_cast<size_t>(b)]++)] = a;
  }
}

}  // namespace edgedeform
