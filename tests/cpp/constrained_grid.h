// A bumpy grid with two constraint sets, shared by the operator-cache, factor-cache,
// warm-state and fixed-point-iteration tests: `whole` (top row handles, bottom row static)
// and `part`, which also pins a band of three rows across (a handle group added).
#pragma once

#include "system/constrained_system.h"
#include "mesh/edge_topology.h"
#include "mesh/mesh_checks.h"
#include "mesh/node_graph.h"
#include "test_meshes.h"

namespace edgedeform::test {

struct ConstrainedGrid {
  static constexpr int kNx = 9, kNy = 8;
  TestMesh mesh = grid(kNx, kNy, 0.3);
  EdgeTopology topo;
  MeshIncidence incidence;
  NodeGraph g;
  std::vector<bool> referenced;
  ConstraintSets whole_sets, part_sets;

  explicit ConstrainedGrid(Domain domain) {
    const int n = static_cast<int>(mesh.V.rows());
    topo = build_edge_topology(mesh.F, n);
    incidence = mesh_incidence(mesh.F, n);
    g = build_node_graph(mesh.V, mesh.F, topo, domain, true);
    referenced = referenced_vertices(mesh.F, n);
    for (int i = 0; i < kNx; ++i) {
      whole_sets.handles.push_back((kNy - 1) * kNx + i);  // top row
      whole_sets.statics.push_back(i);                    // bottom row
    }
    part_sets = whole_sets;
    for (int v = 3 * kNx; v < 6 * kNx; ++v) part_sets.handles.push_back(v);  // rows 3-5
  }
  VertexNeighbours neighbours() const { return {mesh.F, incidence}; }
  ConstrainedSystem layout(const ConstraintSets& s) const {
    return constrained_layout(g, mesh.V, neighbours(), referenced, s);
  }
  ConstrainedSystem whole(const ConstraintSets& s) const {
    return build_constrained_system(g, mesh.V, neighbours(), referenced, s);
  }
  // Targets of s's handles: the top row raised by `lift`, the others where they are.
  RowMatrixX3d targets(const ConstraintSets& s, double lift) const {
    RowMatrixX3d t(static_cast<Eigen::Index>(s.handles.size()), 3);
    for (size_t k = 0; k < s.handles.size(); ++k) {
      t.row(static_cast<Eigen::Index>(k)) = mesh.V.row(s.handles[k]);
      if (k < static_cast<size_t>(kNx)) t(static_cast<Eigen::Index>(k), 2) += lift;
    }
    return t;
  }
};

}  // namespace edgedeform::test
