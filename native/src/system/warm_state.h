// The warm state of live editing: the local fit (rotations, scales, SVD frames) the next
// solve starts from. It is kept twice over: per term of the current constraint set, as the
// last solve left it (a live drag reuses it as it is), and per graph node, once the set
// changes and its terms are renumbered. Only nodes some solve fitted are kept per node (a
// hash map, not an array over the graph): a small region of a 560k-vertex mesh would
// otherwise carry 255 MB of identity rotations.
//
// Invalidation: store() after each solve makes the per-term fit valid; a constraint change
// (keep_per_node) moves it into the per-node copy; starting_fit() hands the per-term fit
// over (it is then the solve's, until stored again).
#pragma once

#include <unordered_map>
#include <vector>

#include "system/constrained_system.h"
#include "local_fit/local_step.h"

namespace edgedeform {

class WarmState {
 public:
  // No fit yet: every node at R = I, s = 1.
  WarmState() = default;

  // The fit a solve on `system` starts from. warm = warm start without an initial shape.
  // - warm, with a stored fit of this set: that fit, moved out (no copies).
  // - warm after a constraint change: each term takes its node's last rotation, SVD frame
  //   and scale.
  // - otherwise (cold, or an initial shape): R = I, V = I, s = 1, so that the result does not
  //   depend on what was solved before.
  LocalFit starting_fit(const ConstrainedSystem& system, bool warm);

  // Keeps `fit`, per term of the set just solved, for the next warm start.
  void store(LocalFit fit);
  // Whether a stored fit of the current set is waiting (starting_fit would return it).
  bool has_fit() const { return last_fit_valid_; }

  // The constraints are about to change: the stored fit of the current set (whose active
  // nodes are term_nodes) is kept per node.
  void keep_per_node(const std::vector<int>& term_nodes);

 private:
  LocalFit last_fit_;
  bool last_fit_valid_ = false;
  struct NodeFit {
    Eigen::Matrix3d rotation;
    Eigen::Matrix3d right_vectors;  // starts the next SVD of the node
    double scale;
  };
  std::unordered_map<int, NodeFit> node_fit_;  // graph node -> its last solved fit
};

}  // namespace edgedeform
