#include "mesh/region_by_distance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "base/parallel.h"

namespace edgedeform {

namespace {

using Point = std::array<double, 3>;

double dist2(const Point& a, const Point& b) {
  const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
  return dx * dx + dy * dy + dz * dz;
}

// A k-d tree over the seed positions, kept as one array in place: each range's middle
// element is the median on the range's widest axis, its halves on either side. Asking
// "is any seed within r" costs about log(#seeds) per vertex, where checking every seed
// would make a large selection on a large mesh quadratic.
class SeedTree {
 public:
  explicit SeedTree(std::vector<Point> points) : p_(std::move(points)), axis_(p_.size(), 0) {
    build(0, static_cast<int>(p_.size()));
  }

  // Index (into points(), a permutation of the seeds) of a seed within r of q, or -1.
  int any_within(const Point& q, double r2) const { return search(q, r2, 0, static_cast<int>(p_.size())); }
  const std::vector<Point>& points() const { return p_; }

 private:
  static constexpr int kLeaf = 8;  // ranges this small are scanned

  void build(int lo, int hi) {
    if (hi - lo <= kLeaf) return;
    Point mn = p_[static_cast<size_t>(lo)], mx = mn;
    for (int k = lo; k < hi; ++k)
      for (int c = 0; c < 3; ++c) {
        mn[c] = std::min(mn[c], p_[static_cast<size_t>(k)][c]);
        mx[c] = std::max(mx[c], p_[static_cast<size_t>(k)][c]);
      }
    int a = 0;
    for (int c = 1; c < 3; ++c)
      if (mx[c] - mn[c] > mx[a] - mn[a]) a = c;
    const int mid = lo + (hi - lo) / 2;
    std::nth_element(p_.begin() + lo, p_.begin() + mid, p_.begin() + hi,
                     [a](const Point& x, const Point& y) { return x[a] < y[a]; });
    axis_[static_cast<size_t>(mid)] = static_cast<char>(a);
    build(lo, mid);
    build(mid + 1, hi);
  }

  int search(const Point& q, double r2, int lo, int hi) const {
    if (hi - lo <= kLeaf) {
      for (int k = lo; k < hi; ++k)
        if (dist2(q, p_[static_cast<size_t>(k)]) <= r2) return k;
      return -1;
    }
    const int mid = lo + (hi - lo) / 2;
    const Point& m = p_[static_cast<size_t>(mid)];
    if (dist2(q, m) <= r2) return mid;
    const int a = axis_[static_cast<size_t>(mid)];
    const double d = q[static_cast<size_t>(a)] - m[static_cast<size_t>(a)];
    const bool left_first = d < 0.0;
    const int near = left_first ? search(q, r2, lo, mid) : search(q, r2, mid + 1, hi);
    // The other side lies at least |d| away along the split axis.
    if (near >= 0 || d * d > r2) return near;
    return left_first ? search(q, r2, mid + 1, hi) : search(q, r2, lo, mid);
  }

  std::vector<Point> p_;
  std::vector<char> axis_;  // split axis, at each range's middle index
};

Point point(const RowMatrixX3d& V, int v) { return {V(v, 0), V(v, 1), V(v, 2)}; }

std::vector<int> within_straight_line(const RowMatrixX3d& V, const std::vector<int>& seeds, double radius) {
  const int n = static_cast<int>(V.rows());
  std::vector<Point> points;
  points.reserve(seeds.size());
  for (int s : seeds) points.push_back(point(V, s));
  const SeedTree tree(std::move(points));
  // r^2 overflows to inf for a huge radius: then every vertex is inside, as it should be.
  const double r2 = radius * radius;
  std::vector<char> inside(static_cast<size_t>(n), 0);
  // Outside the seeds' box grown by r nothing is inside; within it, the seed that held the
  // previous vertex is tried first (neighbouring ids tend to be neighbours on the mesh).
  Point lo = tree.points().front(), hi = lo;
  for (const Point& p : tree.points())
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[c]), hi[c] = std::max(hi[c], p[c]);
  // A little wider than r: only a prefilter, it must never cut what dist2 <= r^2 lets in.
  const double margin = 1.000001 * radius;
  for (int c = 0; c < 3; ++c) lo[c] -= margin, hi[c] += margin;
  parallel_for(n, 4096, 16384, [&](int begin, int end) {
    int witness = -1;
    for (int v = begin; v < end; ++v) {
      const Point q = point(V, v);
      if (q[0] < lo[0] || q[1] < lo[1] || q[2] < lo[2] || q[0] > hi[0] || q[1] > hi[1] || q[2] > hi[2]) continue;
      if (witness < 0 || dist2(q, tree.points()[static_cast<size_t>(witness)]) > r2)
        witness = tree.any_within(q, r2);
      inside[static_cast<size_t>(v)] = witness >= 0 ? 1 : 0;
    }
  });
  std::vector<int> region;
  for (int v = 0; v < n; ++v)
    if (inside[static_cast<size_t>(v)]) region.push_back(v);
  return region;
}

// The distance to p0 across the triangle (p1, p2, p0) from a source d1 from p1 and d2 from
// p2 (the update of fast marching, and of Blender's Connected Only): the triangle is unfolded
// into the plane with the source on the far side of the edge p1 p2; if the straight line from
// the source to p0 crosses that edge, it is the distance, else the path turns at p1 or p2.
double across_triangle(const Eigen::RowVector3d& p0, const Eigen::RowVector3d& p1, const Eigen::RowVector3d& p2,
                       double d1, double d2) {
  const double via_corner = std::min(d1 + (p0 - p1).norm(), d2 + (p0 - p2).norm());
  const Eigen::RowVector3d edge = p2 - p1;
  const double L = edge.norm();
  if (!(L > 0.0)) return via_corner;
  const double x0 = (p0 - p1).dot(edge) / L;
  const double y0 = std::sqrt(std::max((p0 - p1).squaredNorm() - x0 * x0, 0.0));
  const double sx = (d1 * d1 - d2 * d2 + L * L) / (2.0 * L);
  const double sy2 = d1 * d1 - sx * sx;
  if (!(sy2 >= 0.0) || !(y0 > 0.0)) return via_corner;  // no source fits d1, d2; or p0 on the edge's line
  const double sy = -std::sqrt(sy2);
  const double cross = sx + (x0 - sx) * (-sy) / (y0 - sy);  // where the line meets the edge's line
  if (cross < 0.0 || cross > L) return via_corner;
  return std::min(std::hypot(x0 - sx, y0 - sy), via_corner);
}

// Distances over the surface from the seeds, as Blender's Connected Only measures them: along
// the edges, and across each face from its two other corners (across_triangle), kept up to
// date by a priority queue that re-examines a vertex whenever its distance drops (a face's
// estimate can undercut a vertex already taken). Never queues a vertex beyond the radius: its cost grows
// with the region, apart from the arrays over the whole mesh.
std::vector<int> within_over_surface(const RowMatrixX3d& V, const VertexNeighbours& neighbours,
                                     const std::vector<int>& seeds, double radius) {
  const int n = static_cast<int>(V.rows());
  const RowMatrixX3i& F = neighbours.faces();
  const MeshIncidence& m = neighbours.incidence();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(static_cast<size_t>(n), kInf);
  std::vector<int> source(static_cast<size_t>(n), -1);  // the seed each distance is from
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (int s : seeds)
    if (dist[static_cast<size_t>(s)] > 0.0) {
      dist[static_cast<size_t>(s)] = 0.0;
      source[static_cast<size_t>(s)] = s;
      queue.emplace(0.0, s);
    }
  std::vector<int> region(seeds);  // every vertex reached, once
  auto offer = [&](int u, double du, int from) {
    if (du <= radius && du < dist[static_cast<size_t>(u)]) {
      if (dist[static_cast<size_t>(u)] == kInf) region.push_back(u);
      dist[static_cast<size_t>(u)] = du;
      source[static_cast<size_t>(u)] = from;
      queue.emplace(du, u);
    }
  };
  // Across the face (p1, p2, p0) to p0. Between two seeds' distances the unfolded source is
  // no real point and its estimate can fall below the straight line: it is kept no lower than
  // the chord to the nearer of the two seeds, which it is then counted from.
  auto cross = [&](int p0, int p1, int p2) {
    const int s1 = source[static_cast<size_t>(p1)], s2 = source[static_cast<size_t>(p2)];
    double d0 = across_triangle(V.row(p0), V.row(p1), V.row(p2), dist[static_cast<size_t>(p1)],
                                dist[static_cast<size_t>(p2)]);
    int from = s1;
    if (s1 != s2) {
      const double c1 = (V.row(p0) - V.row(s1)).norm(), c2 = (V.row(p0) - V.row(s2)).norm();
      from = c1 <= c2 ? s1 : s2;
      d0 = std::max(d0, std::min(c1, c2));
    }
    offer(p0, d0, from);
  };
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[static_cast<size_t>(v)]) continue;  // a stale entry
    for (int k = m.face_offsets[static_cast<size_t>(v)]; k < m.face_offsets[static_cast<size_t>(v) + 1]; ++k) {
      const int f = m.faces[static_cast<size_t>(k)];
      int a = -1, b = -1;
      for (int c = 0; c < 3; ++c)
        if (F(f, c) != v) (a < 0 ? a : b) = F(f, c);
      const int from = source[static_cast<size_t>(v)];
      offer(a, d + (V.row(a) - V.row(v)).norm(), from);
      offer(b, d + (V.row(b) - V.row(v)).norm(), from);
      if (source[static_cast<size_t>(b)] >= 0) cross(a, v, b);
      if (source[static_cast<size_t>(a)] >= 0) cross(b, v, a);
    }
  }
  std::sort(region.begin(), region.end());
  region.erase(std::unique(region.begin(), region.end()), region.end());
  return region;
}

}  // namespace

std::vector<int> vertices_within_distance(const RowMatrixX3d& V, const VertexNeighbours& neighbours,
                                          const std::vector<int>& seeds, double radius, bool over_surface) {
  if (!(std::isfinite(radius) && radius > 0.0)) {
    std::ostringstream msg;
    msg << "roi_radius must be a finite distance > 0, got " << radius;
    throw std::invalid_argument(msg.str());
  }
  const int n = static_cast<int>(V.rows());
  if (over_surface && neighbours.n_vertices() != n)
    throw std::invalid_argument("the mesh incidence has " + std::to_string(neighbours.n_vertices()) + " vertices, V has " +
                                std::to_string(n));
  for (int s : seeds)
    if (s < 0 || s >= n)
      throw std::out_of_range("seed vertex " + std::to_string(s) + " is out of range [0, " + std::to_string(n) + ")");
  if (seeds.empty()) return {};
  return over_surface ? within_over_surface(V, neighbours, seeds, radius) : within_straight_line(V, seeds, radius);
}

}  // namespace edgedeform
