// The iteration in progress between solves, with its transitions named: a warm solve with
// the same targets continues it (live editing that stands still settles to the cold solve's
// fixed point); any other change restarts it. The Deformer calls the transitions; the
// strategies only move the point and their own memory.
#pragma once

#include <vector>

#include "strategies/fixed_point_iteration.h"
#include "base/iteration_point.h"
#include "strategies/quasi_newton.h"
#include "base/types.h"

namespace edgedeform {

class IterationState {
 public:
  IterationPoint point;
  PlainAndersonMemory plain;          // the plain/Anderson strategy's state (fixed_point_iteration.h)
  QuasiNewtonMemory quasi_newton;    // L-BFGS's state (quasi_newton.h)
  // The strategy that last moved the point: another one's memory no longer describes it.
  Acceleration last_method = Acceleration::Automatic;  // Automatic: none yet

  // New operators (constraints or stiffness): a new map G, so the fit is no longer y's.
  void system_changed() { point.fitted = false; }
  // The free vertices changed: y no longer holds their positions.
  void free_set_changed() { positions_valid_ = false; }
  // A solve was interrupted: its fit is not kept, so the next solve starts afresh.
  void interrupted() { point.fitted = false; }
  // A solve finished: y holds the free vertices of the current constraints.
  void finished() { positions_valid_ = true; }

  // Whether a solve towards `targets` continues this iteration (the warm fit must be there too).
  bool continues(const RowMatrixX3d& targets) const {
    return point.fitted && targets_.rows() == targets.rows() && targets_ == targets;
  }
  // Starts afresh towards `targets`: y from the last solve's positions when `keep_positions`
  // and they are the current free vertices', else from rest; the strategies' state reset.
  void restart(const RowMatrixX3d& targets, const RowMatrixX3d& rest, const std::vector<int>& free_vertices,
               bool keep_positions, int anderson_window);
  // y set to `initial`'s free rows, whose fit the caller computes next.
  void start_at(const RowMatrixX3d& initial, const std::vector<int>& free_vertices);

 private:
  RowMatrixX3d targets_;         // the targets the iteration moves towards
  bool positions_valid_ = false;  // y holds the free vertices of the current constraints
};

}  // namespace edgedeform
