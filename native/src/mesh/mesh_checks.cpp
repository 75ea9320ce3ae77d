#include "mesh/mesh_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include "mesh/cotangent.h"

namespace edgedeform {

void check_finite(const RowMatrixX3d& X, const char* what) {
  for (Eigen::Index r = 0; r < X.rows(); ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(X(r, c)))
        throw std::invalid_argument(std::string(what) + " has a non-finite value (" +
                                    std::to_string(X(r, c)) + ") at row " + std::to_string(r));
}

void check_mesh(const RowMatrixX3d& V, const RowMatrixX3i& F) {
  if (V.rows() == 0) throw std::invalid_argument("V has no vertices");
  if (F.rows() == 0) throw std::invalid_argument("F has no faces");
  check_finite(V, "V");
  const int n = static_cast<int>(V.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = F(f, k);
      if (v < 0 || v >= n)
        throw std::out_of_range("F[" + std::to_string(f) + "] has vertex index " + std::to_string(v) +
                                ", outside [0, " + std::to_string(n) + ")");
    }
    if (F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0))
      throw std::invalid_argument("F[" + std::to_string(f) + "] repeats a vertex (" +
                                  std::to_string(F(f, 0)) + ", " + std::to_string(F(f, 1)) + ", " +
                                  std::to_string(F(f, 2)) + ")");
  }
}

namespace {

// A face the solver cannot use: every angle's sine is below the cotangent floor (zero area,
// a needle, or corners at one point).
bool is_degenerate_face(const RowMatrixX3d& V, const RowMatrixX3i& F, Eigen::Index f) {
  const Eigen::Vector3d a = V.row(F(f, 0)).transpose();
  const Eigen::Vector3d u = V.row(F(f, 1)).transpose() - a, v = V.row(F(f, 2)).transpose() - a;
  const Eigen::Vector3d w = v - u;
  const double twice_area = u.cross(v).norm();
  const double longest = std::max({u.norm(), v.norm(), w.norm()});
  return !(twice_area > kSinFloor * longest * longest);
}

std::string point_text(const RowMatrixX3d& V, int v) {
  std::ostringstream s;
  s << "(" << V(v, 0) << ", " << V(v, 1) << ", " << V(v, 2) << ")";
  return s.str();
}

}  // namespace

std::vector<int> connected_pieces(const RowMatrixX3i& F, int n) {
  // Union-find with path halving; faces join their three vertices.
  std::vector<int> parent(static_cast<size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&parent](int v) {
    while (parent[static_cast<size_t>(v)] != v) {
      parent[static_cast<size_t>(v)] = parent[static_cast<size_t>(parent[static_cast<size_t>(v)])];
      v = parent[static_cast<size_t>(v)];
    }
    return v;
  };
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 1; k < 3; ++k) parent[static_cast<size_t>(root(F(f, k)))] = root(F(f, 0));
  for (int v = 0; v < n; ++v) parent[static_cast<size_t>(v)] = root(v);
  return parent;
}

void check_geometry(const RowMatrixX3d& V, const RowMatrixX3i& F) {
  const int n = static_cast<int>(V.rows());
  const std::vector<int> piece = connected_pieces(F, n);
  // Per piece: its faces, and how many of them the solver can use.
  std::vector<int> faces(static_cast<size_t>(n), 0), usable(static_cast<size_t>(n), 0), first(static_cast<size_t>(n), -1);
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const auto r = static_cast<size_t>(piece[static_cast<size_t>(F(f, 0))]);
    if (first[r] < 0) first[r] = static_cast<int>(f);
    ++faces[r];
    usable[r] += !is_degenerate_face(V, F, f);
  }
  int pieces = 0, degenerate_pieces = 0;
  size_t worst = 0;
  for (size_t r = 0; r < faces.size(); ++r) {
    if (faces[r] == 0) continue;
    ++pieces;
    if (usable[r] == 0 && (degenerate_pieces++ == 0 || faces[r] > faces[worst])) worst = r;
  }
  if (degenerate_pieces == 0) return;
  // Name what is wrong with the geometry, not what the solver would later fail at.
  const std::vector<bool> used = referenced_vertices(F, n);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  int in_worst = 0;
  for (int v = 0; v < n; ++v)
    if (used[static_cast<size_t>(v)] && static_cast<size_t>(piece[static_cast<size_t>(v)]) == worst) {
      lo = lo.cwiseMin(V.row(v).transpose());
      hi = hi.cwiseMax(V.row(v).transpose());
      ++in_worst;
    }
  const bool one_point = (hi - lo).maxCoeff() == 0.0;
  const std::string shape = one_point ? "all its " + std::to_string(in_worst) + " vertices are at one point " +
                                            point_text(V, F(first[worst], 0))
                                      : "every face has zero area (its vertices lie on one line)";
  if (pieces == 1) throw std::invalid_argument("the mesh is degenerate: " + shape);
  throw std::invalid_argument(std::to_string(degenerate_pieces) + " of the mesh's " + std::to_string(pieces) +
                              " connected pieces are degenerate; in the one with face " +
                              std::to_string(first[worst]) + ", " + shape);
}

double largest_safe_distance(double total_weight) {
  // Energies add w * |d|^2 over every arc (and the Laplacian term squares sums of w * d):
  // keep (sum |w|)^2 * |d|^2 and (sum |w|) * |d|^2 a factor 1e4 below the largest double.
  const double w = std::max(total_weight, 1.0);
  return std::sqrt(std::numeric_limits<double>::max() * 1e-4) / w;
}

void check_distance(const RowMatrixX3d& X, const Eigen::RowVector3d& center, double limit, const char* what) {
  for (Eigen::Index r = 0; r < X.rows(); ++r) {
    const double d = (X.row(r) - center).cwiseAbs().maxCoeff();
    if (!(d <= limit)) {
      std::ostringstream s;
      s << what << "[" << r << "] = (" << X(r, 0) << ", " << X(r, 1) << ", " << X(r, 2) << ") is " << d
        << " from the mesh's centre: too far to solve without overflow (at most " << limit << ")";
      throw std::invalid_argument(s.str());
    }
  }
}

void check_index_set(const std::vector<int>& indices, int n, const char* what) {
  std::vector<bool> seen(static_cast<size_t>(n), false);
  for (size_t k = 0; k < indices.size(); ++k) {
    const int v = indices[k];
    if (v < 0 || v >= n)
      throw std::out_of_range(std::string(what) + "[" + std::to_string(k) + "] = " + std::to_string(v) +
                              " is outside [0, " + std::to_string(n) + ")");
    if (seen[static_cast<size_t>(v)])
      throw std::invalid_argument(std::string(what) + " lists vertex " + std::to_string(v) + " twice");
    seen[static_cast<size_t>(v)] = true;
  }
}

std::vector<bool> referenced_vertices(const RowMatrixX3i& F, int n) {
  std::vector<bool> used(static_cast<size_t>(n), false);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<size_t>(F(f, k))] = true;
  return used;
}

}  // namespace edgedeform
