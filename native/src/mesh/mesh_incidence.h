// What the Deformer keeps of a mesh's connectivity: the faces around each vertex and the
// number every edge has in the edge topology's order, without the topology, the node graph
// or a vertex adjacency. A region's graph is built from these (region_graph.h) in time and
// memory of the region, whatever the mesh's size (record 0058); the walks over the surface
// (regions over the surface, components) step through a vertex's faces (VertexNeighbours).
#pragma once

#include <vector>

#include "base/types.h"

namespace edgedeform {

struct MeshIncidence {
  // The faces using v, ascending: faces[face_offsets[v] .. face_offsets[v + 1]).
  std::vector<int> face_offsets{0};
  std::vector<int> faces;
  // Edge (a, b), a < b, is row edge_offsets[a] + k of build_edge_topology's edges, where b is
  // a's k-th neighbour above a: the topology's rows are (a, b) in lexicographic order.
  std::vector<int> edge_offsets{0};

  int n_vertices() const { return static_cast<int>(face_offsets.size()) - 1; }
  int n_edges() const { return edge_offsets.back(); }
};

// Of faces F over n vertices (indices checked by check_mesh; no face repeats a vertex).
MeshIncidence mesh_incidence(const RowMatrixX3i& F, int n);

// A mesh's faces with their incidence: who neighbours whom. Holds references: both must
// outlive it.
class VertexNeighbours {
 public:
  VertexNeighbours(const RowMatrixX3i& faces, const MeshIncidence& incidence) : F_(faces), m_(incidence) {}

  int n_vertices() const { return m_.n_vertices(); }
  const RowMatrixX3i& faces() const { return F_; }
  const MeshIncidence& incidence() const { return m_; }

  // visit(u) for every neighbour u of v, once per face they share: a walk that keeps the
  // first visit needs no sorting.
  template <class Visit>
  void for_each(int v, Visit&& visit) const {
    for (int s = m_.face_offsets[static_cast<size_t>(v)]; s < m_.face_offsets[static_cast<size_t>(v) + 1]; ++s) {
      const int f = m_.faces[static_cast<size_t>(s)];
      for (int k = 0; k < 3; ++k)
        if (F_(f, k) != v) visit(F_(f, k));
    }
  }
  // v's neighbours, ascending, once each.
  void sorted(int v, std::vector<int>& out) const;
  // The edge topology's row of edge {a, b}; -1 when no face has both.
  int edge_id(int a, int b) const;

 private:
  const RowMatrixX3i& F_;
  const MeshIncidence& m_;
};

}  // namespace edgedeform
