// The part of the node graph a region's terms need, built from the faces around the region
// instead of the whole mesh's graph (record 0058): at 560k vertices the whole graph was
// ~140 MB and 234 ms for a region of 20k free vertices whose part is a few MB.
//
// The part's vertices and nodes are numbered in the mesh's order (a monotone map), and its
// faces keep theirs, so every term whose arcs the part holds whole has the arcs, weights and
// neighbour order of the whole graph, bit for bit.
#pragma once

#include <vector>

#include "mesh/mesh_incidence.h"
#include "mesh/node_graph.h"

namespace edgedeform {

// A node graph with the mesh's ids of its vertices and nodes; rest holds its vertices' rest
// positions by its own vertex ids. Null maps: its ids are the mesh's.
struct GraphPart {
  const NodeGraph* graph = nullptr;
  const RowMatrixX3d* rest = nullptr;
  const std::vector<int>* vertices = nullptr;
  const std::vector<int>* nodes = nullptr;

  int mesh_vertex(int v) const { return vertices ? (*vertices)[static_cast<size_t>(v)] : v; }
  int mesh_node(int i) const { return nodes ? (*nodes)[static_cast<size_t>(i)] : i; }
};

struct RegionGraph {
  NodeGraph graph;
  RowMatrixX3d rest;
  std::vector<int> vertices;  // ascending mesh vertex ids
  std::vector<int> nodes;     // ascending mesh node ids

  GraphPart part() const { return {&graph, &rest, &vertices, &nodes}; }
};

// The faces (ascending) within two vertex rings of `seeds`: the faces of the seeds, then every
// face sharing a vertex with those. A term whose node has a seed vertex, or neighbours such a
// node, has all its arcs in these faces, in either domain.
std::vector<int> faces_around(const VertexNeighbours& neighbours, const std::vector<int>& seeds);

// The node graph of `faces` (ascending ids into neighbours.faces()) with the mesh's ids.
RegionGraph region_graph(const RowMatrixX3d& V, const VertexNeighbours& neighbours, const std::vector<int>& faces,
                         Domain domain, bool clamp_negative_weights);

}  // namespace edgedeform
