// The derivative of the local step (docs/design.md §4, "Reaching the fixed point"): how each term's
// fitted rotation R_t and scale s_t move when the node positions move by dp.
//
// Rotations move on the left, R_t + dR_t = (I + [omega_t]x) R_t. The fit maximizes
// tr(R S) over rotations, so at the fit N = R S is symmetric; differentiating that gives
//     ((tr N) I - N) omega = -vee(R dS - (R dS)^T),       dS = sum_a w_a e0_a de_a^T,
// whose matrix has the eigenvalues sigma_i + sigma_j of S's (signed) singular values: a pair
// that sums to ~0 (a degenerate or reflected neighbourhood) makes the rotation about that
// axis undefined, and that direction is dropped (a pseudo-inverse), as the fit itself then
// takes it from a tie-breaker. The scale s_t = tr(N) / rest_norm moves by tr(R dS) /
// rest_norm (the rotation's own change drops out: tr([omega]x N) = 0 for symmetric N), and
// not at all where it is clamped (local_step.h's kMinScale, kMaxScale).
// Not modelled: a term whose weighted arcs are collinear (its weights clamped to 0 by right
// or obtuse angles) takes its spin about the main axis from the unweighted arcs
// (local_step.cpp); that spin's change is left out, so J_G is inexact at such terms (the
// claim check's modulus there is an estimate; the fixed point is unchanged).
#pragma once

#include <vector>

#include "local_fit/local_step.h"

namespace edgedeform {

// The local fit linearized at node positions p: per term what turns a covariance change dS
// into (omega_t, ds_t).
struct FitLinearization {
  std::vector<Eigen::Matrix3d> omega_map;  // -((tr N) I - N)^+ per term (zero for a rest-free term)
  Eigen::VectorXd scale_gain;              // 1 / rest_norm where s_t is not clamped, else 0
};

// Linearizes `fit` (fit_local's result at node positions p) with the same stencil.
FitLinearization linearize_fit(const NodeStencil& stencil, const RowMatrixX3d& node_positions, const LocalFit& fit);

// A term's response to a change dS of its covariance: omega (rotation) and the scale change.
inline void fit_response(const Eigen::Matrix3d& R, const Eigen::Matrix3d& omega_map, double scale_gain,
                         const Eigen::Matrix3d& dS, Eigen::Vector3d& omega, double& dscale) {
  const Eigen::Matrix3d RdS = R * dS;
  // vee(K) for skew K = [k]x: k = (K21, K02, K10)
  const Eigen::Vector3d skew(RdS(2, 1) - RdS(1, 2), RdS(0, 2) - RdS(2, 0), RdS(1, 0) - RdS(0, 1));
  omega = omega_map * skew;
  dscale = scale_gain * RdS.trace();
}

// omega (#terms x 3) and dscale (#terms) for node displacements dp (rows as the positions
// the stencil indexes). In parallel over terms, each term on its own: the same on any
// number of threads.
void differentiate_fit(const NodeStencil& stencil, const LocalFit& fit, const FitLinearization& linearization,
                       const RowMatrixX3d& dp, RowMatrixX3d& omega, Eigen::VectorXd& dscale);

}  // namespace edgedeform
