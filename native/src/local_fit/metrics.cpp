#include "local_fit/metrics.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "mesh/edge_topology.h"
#include "local_fit/local_step.h"
#include "mesh/mesh_checks.h"
#include "mesh/node_graph.h"

namespace edgedeform {

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d row3(const RowMatrixX3d& X, int v) { return X.row(v).transpose(); }

// Signed dihedral angle at edge (a,b) between faces f and g, 0 when flat.
double dihedral(const RowMatrixX3d& X, const RowMatrixX3i& F, int f, int g, int a, int b) {
  auto normal = [&](int face) {
    return (row3(X, F(face, 1)) - row3(X, F(face, 0))).cross(row3(X, F(face, 2)) - row3(X, F(face, 0)));
  };
  const Eigen::Vector3d n1 = normal(f), n2 = normal(g);
  const Eigen::Vector3d e = (row3(X, b) - row3(X, a)).normalized();
  return std::atan2(e.dot(n1.cross(n2)), n1.dot(n2));
}

}  // namespace

QualityMetrics compute_metrics(const RowMatrixX3d& rest, const RowMatrixX3i& F, const RowMatrixX3d& X,
                               const std::vector<int>& handles, const RowMatrixX3d& targets) {
  check_mesh(rest, F);
  const int n = static_cast<int>(rest.rows());
  if (X.rows() != n)
    throw std::invalid_argument("deformed has " + std::to_string(X.rows()) + " rows, rest has " + std::to_string(n));
  check_finite(X, "deformed");
  check_index_set(handles, n, "handles");
  if (targets.rows() != static_cast<Eigen::Index>(handles.size()))
    throw std::invalid_argument("targets has " + std::to_string(targets.rows()) + " rows, expected one per handle (" +
                                std::to_string(handles.size()) + ")");
  check_finite(targets, "targets");

  QualityMetrics q;
  for (size_t h = 0; h < handles.size(); ++h)
    q.handle_error = std::max(q.handle_error, (X.row(handles[h]) - targets.row(static_cast<Eigen::Index>(h))).norm());

  const EdgeTopology topo = build_edge_topology(F, n);
  int strained = 0;
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    const int a = topo.edges(e, 0), b = topo.edges(e, 1);
    const double l0 = (rest.row(a) - rest.row(b)).norm();
    if (!(l0 > 0.0)) continue;
    const double strain = std::abs((X.row(a) - X.row(b)).norm() - l0) / l0;
    q.mean_edge_strain += strain;
    q.max_edge_strain = std::max(q.max_edge_strain, strain);
    ++strained;
  }
  if (strained > 0) q.mean_edge_strain /= strained;

  // The faces around every edge (CSR): two at an interior edge, k > 2 at a non-manifold one.
  std::vector<int> first(static_cast<size_t>(topo.edges.rows()) + 1, 0);
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e)
    first[static_cast<size_t>(e) + 1] = first[static_cast<size_t>(e)] + topo.face_count(e);
  std::vector<int> edge_faces(static_cast<size_t>(first.back()));
  std::vector<int> cursor(first.begin(), first.end() - 1);
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      edge_faces[static_cast<size_t>(cursor[static_cast<size_t>(topo.face_edges(f, k))]++)] = static_cast<int>(f);
  // Every pair of faces at an edge is one hinge; a fin's edge has three.
  int hinges = 0;
  for (Eigen::Index e = 0; e < topo.edges.rows(); ++e) {
    const int a = topo.edges(e, 0), b = topo.edges(e, 1);
    for (int s = first[static_cast<size_t>(e)]; s < first[static_cast<size_t>(e) + 1]; ++s)
      for (int t = s + 1; t < first[static_cast<size_t>(e) + 1]; ++t) {
        const int f = edge_faces[static_cast<size_t>(s)], g = edge_faces[static_cast<size_t>(t)];
        double change = std::abs(dihedral(X, F, f, g, a, b) - dihedral(rest, F, f, g, a, b));
        if (change > kPi) change = 2.0 * kPi - change;
        q.mean_dihedral_change += change;
        ++hinges;
      }
  }
  if (hinges > 0) q.mean_dihedral_change /= hinges;

  const NodeGraph primal = build_node_graph(rest, F, topo, Domain::Primal, /*clamp_negative_weights=*/true);
  std::vector<int> all(static_cast<size_t>(n));
  for (int v = 0; v < n; ++v) all[static_cast<size_t>(v)] = v;
  const NodeStencil st = build_stencil(primal, rest, all, all);
  LocalFit fit;
  fit_local(st, X, Eigen::VectorXd::Ones(n), fit);
  q.arap_energy = fit.energy;
  const double scale = st.rest_norm.sum();
  q.arap_energy_normalized = scale > 0.0 ? fit.energy / scale : 0.0;
  return q;
}

}  // namespace edgedeform
