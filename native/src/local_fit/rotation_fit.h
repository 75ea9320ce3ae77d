// The rotation of the local step: the R maximizing trace(R S) for S = sum_j w e0_j e_j^T.
#pragma once

#include <Eigen/Core>

namespace edgedeform {

// Below this ratio sigma2 / sigma1 the fit fixes only the main axis (R u1 = v1); the
// rotation about it is then noise of S and is taken from the tie-breaker instead.
constexpr double kDegenerateRatio = 1e-6;

struct RotationFit {
  Eigen::Matrix3d R;
  bool degenerate = false;   // sigma2 < kDegenerateRatio * sigma1 (R then maps u1 to v1)
  Eigen::Vector3d u1, v1;    // main singular pair: S v1 = sigma1 u1
};

// For S = U Sigma V^T: R = V U^T, with the column of the smallest singular value flipped when
// det(V U^T) < 0. `V` is the starting guess of the right singular vectors (any orthogonal
// matrix; the previous iteration's makes this cheap) and returns the converged ones.
// With `near` (the previous iteration's rotation of this node), Newton's method on SO(3)
// is tried first: from a close start it reaches the same optimum in two or three cheap
// steps; far starts and degenerate S go to the SVD.
RotationFit fit_rotation(const Eigen::Matrix3d& S, Eigen::Matrix3d& V, const Eigen::Matrix3d* near = nullptr);

// Newton's method for max trace(R S) over rotations, from `R` (updated in place). Returns
// false, leaving R as it was, when the start is far or the optimum is not well defined.
bool refine_rotation(const Eigen::Matrix3d& S, Eigen::Matrix3d& R);

// refine_rotation for two terms at once, in the two lanes of a SIMD register, with the same
// arithmetic (and results) per lane as two separate calls. Bit k of the result is set when
// R[k] was refined; the other R[k] are left as they were.
int refine_rotation_pair(const Eigen::Matrix3d* const S[2], Eigen::Matrix3d* const R[2]);

// For a degenerate fit: among the rotations with R u1 = v1, the one maximizing
// trace(R tie_breaker) (the minimal rotation u1 -> v1 when the tie-breaker does not decide).
Eigen::Matrix3d rotation_about_axis(const Eigen::Vector3d& u1, const Eigen::Vector3d& v1,
                                    const Eigen::Matrix3d& tie_breaker);

// fit_rotation alone, for callers without a tie-breaker.
inline Eigen::Matrix3d closest_rotation(const Eigen::Matrix3d& S) {
  Eigen::Matrix3d V = Eigen::Matrix3d::Identity();
  return fit_rotation(S, V).R;
}

}  // namespace edgedeform
