// A 20 x 20 bumpy grid, its bottom row static and its top row the handle, as a constrained
// system on the edge graph: the coarse-space tests' problem.
#pragma once

#include <optional>
#include <vector>

#include "edgedeform/constrained_system.h"
#include "edgedeform/edge_topology.h"
#include "edgedeform/node_graph.h"
#include "test_meshes.h"

namespace edgedeform::test {

struct GridLift {
  TestMesh mesh = grid(20, 20, 0.3);
  EdgeTopology topology;
  NodeGraph graph;
  ConstrainedSystem system;
  explicit GridLift(std::optional<std::vector<int>> roi = std::nullopt) {
    topology = build_edge_topology(mesh.F, static_cast<int>(mesh.V.rows()));
    graph = build_node_graph(mesh.V, mesh.F, topology, Domain::Edge, true);
    ConstraintSets sets;
    for (int i = 0; i < 20; ++i) {
      sets.statics.push_back(i);            // bottom row
      sets.handles.push_back(19 * 20 + i);  // top row
    }
    sets.roi = std::move(roi);
    std::vector<bool> referenced(mesh.V.rows(), true);
    system = build_constrained_system(graph, mesh.V, topology.edges, referenced, sets);
  }
};

}  // namespace edgedeform::test
