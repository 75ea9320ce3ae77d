#include "mesh/region_graph.h"

#include <algorithm>

#include "mesh/edge_topology.h"

namespace edgedeform {

std::vector<int> faces_around(const VertexNeighbours& neighbours, const std::vector<int>& seeds) {
  const MeshIncidence& m = neighbours.incidence();
  std::vector<char> near_face(static_cast<size_t>(neighbours.faces().rows()), 0),
      ring_vertex(static_cast<size_t>(m.n_vertices()), 0);
  auto faces_of = [&](int v, auto&& visit) {
    for (int s = m.face_offsets[static_cast<size_t>(v)]; s < m.face_offsets[static_cast<size_t>(v) + 1]; ++s)
      visit(m.faces[static_cast<size_t>(s)]);
  };
  std::vector<int> ring;  // the seeds and their neighbours: the vertices of the seeds' faces
  for (int v : seeds) {
    if (ring_vertex[static_cast<size_t>(v)]) continue;
    ring_vertex[static_cast<size_t>(v)] = 1;
    ring.push_back(v);
  }
  const size_t n_seeds = ring.size();
  for (size_t r = 0; r < n_seeds; ++r)
    neighbours.for_each(ring[r], [&](int u) {
      if (!ring_vertex[static_cast<size_t>(u)]) {
        ring_vertex[static_cast<size_t>(u)] = 1;
        ring.push_back(u);
      }
    });
  std::vector<int> faces;
  for (int v : ring)
    faces_of(v, [&](int f) {
      if (!near_face[static_cast<size_t>(f)]) {
        near_face[static_cast<size_t>(f)] = 1;
        faces.push_back(f);
      }
    });
  std::sort(faces.begin(), faces.end());
  return faces;
}

RegionGraph region_graph(const RowMatrixX3d& V, const VertexNeighbours& neighbours, const std::vector<int>& faces,
                         Domain domain, bool clamp_negative_weights) {
  const RowMatrixX3i& F = neighbours.faces();
  RegionGraph r;
  // Part vertex ids in ascending mesh order, so that lexicographic orders agree.
  std::vector<int> local(static_cast<size_t>(V.rows()), -1);
  for (int f : faces)
    for (int k = 0; k < 3; ++k) local[static_cast<size_t>(F(f, k))] = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (local[static_cast<size_t>(v)] == 0) {
      local[static_cast<size_t>(v)] = static_cast<int>(r.vertices.size());
      r.vertices.push_back(static_cast<int>(v));
    }
  const auto nv = static_cast<Eigen::Index>(r.vertices.size());
  r.rest.resize(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) r.rest.row(v) = V.row(r.vertices[static_cast<size_t>(v)]);
  RowMatrixX3i part_faces(static_cast<Eigen::Index>(faces.size()), 3);
  for (size_t s = 0; s < faces.size(); ++s)
    for (int k = 0; k < 3; ++k) part_faces(static_cast<Eigen::Index>(s), k) = local[static_cast<size_t>(F(faces[s], k))];
  std::vector<int>().swap(local);

  const EdgeTopology topology = build_edge_topology(part_faces, static_cast<int>(nv));
  r.graph = build_node_graph(r.rest, part_faces, topology, domain, clamp_negative_weights);
  r.nodes.resize(static_cast<size_t>(r.graph.n_nodes));
  for (int i = 0; i < r.graph.n_nodes; ++i)
    r.nodes[static_cast<size_t>(i)] =
        domain == Domain::Edge
            ? neighbours.edge_id(r.vertices[static_cast<size_t>(r.graph.node_vertices(i, 0))],
                        r.vertices[static_cast<size_t>(r.graph.node_vertices(i, 1))])
            : r.vertices[static_cast<size_t>(i)];
  return r;
}

}  // namespace edgedeform
