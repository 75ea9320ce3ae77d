// The iterate a strategy (plain/Anderson, L-BFGS) continues from call to call: the free
// positions, their energy, and whether the local fit the solve holds is theirs. Owned by
// IterationState (iteration_state.h); the strategies move it, the Deformer's transitions
// decide when it may be continued.
#pragma once

#include <Eigen/Core>

namespace edgedeform {

struct IterationPoint {
  Eigen::MatrixXd y;    // free positions (#free x 3)
  double energy = 0.0;  // E(y), when fitted
  bool fitted = false;  // the solve's fit = fit(y); false for a cold start's first step (R = I, s = 1)
};

}  // namespace edgedeform
