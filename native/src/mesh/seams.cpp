#include "mesh/seams.h"

#include <algorithm>
#include <numeric>
#include <set>
#include <sstream>

#include "mesh/mesh_checks.h"

namespace edgedeform {

SeamCopies find_seam_copies(const RowMatrixX3d& V, const RowMatrixX3i& F) {
  const int n = static_cast<int>(V.rows());
  const std::vector<bool> used = referenced_vertices(F, n);
  std::vector<int> order;
  for (int v = 0; v < n; ++v)
    if (used[static_cast<size_t>(v)]) order.push_back(v);
  auto less = [&V](int a, int b) {
    for (int c = 0; c < 3; ++c)
      if (V(a, c) != V(b, c)) return V(a, c) < V(b, c);
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  SeamCopies s;
  for (size_t i = 0; i < order.size();) {
    size_t j = i + 1;
    while (j < order.size() && V.row(order[j]) == V.row(order[i])) ++j;
    if (j - i > 1) s.groups.emplace_back(order.begin() + static_cast<std::ptrdiff_t>(i), order.begin() + static_cast<std::ptrdiff_t>(j));
    i = j;
  }
  if (!s.groups.empty()) s.piece = connected_pieces(F, n);
  return s;
}

std::optional<std::string> seam_warning(const SeamCopies& seams, const RowMatrixX3d& X, double tolerance) {
  int apart = 0, positions = 0;
  double widest = 0.0;
  std::set<int> pieces;
  for (const std::vector<int>& g : seams.groups) {
    double spread = 0.0;
    for (int v : g) spread = std::max(spread, (X.row(v) - X.row(g.front())).norm());
    if (!(spread > tolerance)) continue;
    apart += static_cast<int>(g.size());
    ++positions;
    widest = std::max(widest, spread);
    for (int v : g) pieces.insert(seams.piece[static_cast<size_t>(v)]);
  }
  if (apart == 0) return std::nullopt;
  std::ostringstream msg;
  msg << "unwelded seam: " << apart << " coincident vertices (" << positions << " shared positions, in "
      << pieces.size() << " connected pieces) moved apart, by up to " << widest
      << "; weld them in the mesh, or pass weld=True to deform the copies together";
  return msg.str();
}

}  // namespace edgedeform
