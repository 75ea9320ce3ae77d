#include "local_fit/rotation_fit.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "local_fit/lanes.h"

namespace edgedeform {

namespace {

// Columns count as orthogonal when their cosine is below this: rotations come out exact to
// about 1e-12, which the fixed-point tests (1e-9 of the diagonal, through the bi-Laplacian
// of lambda = 0) allow; 1e-15 costs a sweep more in about one fit of three.
constexpr double kOrthogonal = 1e-12;

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& k) {
  Eigen::Matrix3d K;
  K << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
  return K;
}

// The smallest rotation taking unit u to unit v.
Eigen::Matrix3d minimal_rotation(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const double c = u.dot(v);
  if (c < -1.0 + 1e-12) {  // opposite: a half turn about any axis orthogonal to u
    const Eigen::Vector3d w = u.unitOrthogonal();
    return 2.0 * w * w.transpose() - Eigen::Matrix3d::Identity();
  }
  const Eigen::Matrix3d K = cross_matrix(u.cross(v));
  return Eigen::Matrix3d::Identity() + K + K * K / (1.0 + c);
}

}  // namespace

int refine_rotation_pair(const Eigen::Matrix3d* const S[2], Eigen::Matrix3d* const R[2]) {
  // f(w) = trace(exp([w]) N), N = R S, has gradient g = (N12-N21, N20-N02, N01-N10) and
  // Hessian -(trace(N) I - sym(N)) at w = 0; the Newton step is w = H^-1 g.
  // Written out (row-major n[3i+j] = N(i,j), r likewise), as this runs for every term in
  // every iteration: only H's lower triangle, 4 divisions per step, no square root (sizes
  // compared squared), two terms per instruction.
  Lanes r[9], s[9], n[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      r[3 * i + j] = Lanes{(*R[0])(i, j), (*R[1])(i, j)};
      s[3 * i + j] = Lanes{(*S[0])(i, j), (*S[1])(i, j)};
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) n[3 * i + j] = r[3 * i] * s[j] + r[3 * i + 1] * s[3 + j] + r[3 * i + 2] * s[6 + j];
  LaneMask active = {-1, -1}, converged = {0, 0};
  for (int step = 0; step < 4 && any(active); ++step) {
    const Lanes g0 = n[5] - n[7], g1 = n[6] - n[2], g2 = n[1] - n[3];
    const Lanes tr = n[0] + n[4] + n[8];
    const Lanes h00 = tr - n[0], h11 = tr - n[4], h22 = tr - n[8];
    const Lanes h10 = -0.5 * (n[3] + n[1]), h20 = -0.5 * (n[6] + n[2]), h21 = -0.5 * (n[7] + n[5]);
    const Lanes h_trace = h00 + h11 + h22;
    // H must be clearly positive definite (a maximum, and not a degenerate S): LDL^T
    // pivots. A lane that fails stops (its division results below are not used).
    const Lanes floor = kDegenerateRatio * h_trace;
    const Lanes d0 = h00;
    const Lanes inv0 = 1.0 / d0;
    const Lanes l10 = h10 * inv0, l20 = h20 * inv0;
    const Lanes d1 = h11 - l10 * h10;
    const Lanes inv1 = 1.0 / d1;
    const Lanes l21 = (h21 - l20 * h10) * inv1;
    const Lanes d2 = h22 - l20 * h20 - l21 * l21 * d1;
    // solve L D L^T w = g
    Lanes w0 = g0, w1 = g1 - l10 * g0;
    Lanes w2 = g2 - l20 * w0 - l21 * w1;
    w0 *= inv0;
    w1 *= inv1;
    w2 /= d2;
    w1 -= l21 * w2;
    w0 -= l10 * w1 + l20 * w2;
    const Lanes size2 = w0 * w0 + w1 * w1 + w2 * w2;
    LaneMask ok = (d0 > floor) & (d1 > floor) & (d2 > floor);
    if (step == 0) ok &= size2 <= 0.09;  // |w| > 0.3, far: quadratic convergence not yet there
    active &= ok;
    if (!any(active)) break;
    // Cayley step Q = I + f([c] + c c^T - |c|^2 I), c = w / 2, f = 2 / (1 + |c|^2): a
    // rotation by ~|w| (to third order), exactly orthogonal.
    const Lanes cx = 0.5 * w0, cy = 0.5 * w1, cz = 0.5 * w2;
    const Lanes c2 = cx * cx + cy * cy + cz * cz, f = 2.0 / (1.0 + c2);
    const Lanes fx = f * cx, fy = f * cy, fz = f * cz, diag = 1.0 - f * c2;
    const Lanes q[9] = {diag + fx * cx, fx * cy - fz,   fx * cz + fy,    //
                        fx * cy + fz,   diag + fy * cy, fy * cz - fx,    //
                        fx * cz - fy,   fy * cz + fx,   diag + fz * cz};
    Lanes next[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) next[3 * i + j] = q[3 * i] * r[j] + q[3 * i + 1] * r[3 + j] + q[3 * i + 2] * r[6 + j];
    for (int k = 0; k < 9; ++k) r[k] = active ? next[k] : r[k];
    // Newton's error after a step of size |w| is about kappa |w|^2, kappa = the pivots'
    // spread h_trace / min(d) (a bound on H's condition): below 1e-12 the rotation is as
    // exact as the SVD's, so the step that would only confirm it is skipped.
    const Lanes d01 = d0 < d1 ? d0 : d1, d_min = d01 < d2 ? d01 : d2;
    const LaneMask done = active & ((size2 < 1e-14) | (h_trace * size2 < 1e-12 * d_min));
    converged |= done;
    active &= ~done;
    if (!any(active)) break;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) next[3 * i + j] = q[3 * i] * n[j] + q[3 * i + 1] * n[3 + j] + q[3 * i + 2] * n[6 + j];
    for (int k = 0; k < 9; ++k) n[k] = next[k];
  }
  int refined = 0;
  for (int k = 0; k < 2; ++k) {
    if (!converged[k]) continue;
    refined |= 1 << k;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) (*R[k])(i, j) = r[3 * i + j][k];
  }
  return refined;
}

bool refine_rotation(const Eigen::Matrix3d& S, Eigen::Matrix3d& R) {
  Eigen::Matrix3d copy = R;
  const Eigen::Matrix3d* const S2[2] = {&S, &S};
  Eigen::Matrix3d* const R2[2] = {&R, &copy};
  return refine_rotation_pair(S2, R2) != 0;
}

// One-sided Jacobi SVD (Hestenes): rotate the columns of A = S V until they are orthogonal,
// so that S V = U Sigma. With the two largest singular pairs (u1,v1), (u2,v2), the optimal
// proper rotation is R = v1 u1^T + v2 u2^T + (v1 x v2)(u1 x u2)^T: both U and V are completed
// to rotations, which is exactly the reflection fix, and it stays defined for rank-2 S (the
// flat neighbourhoods that are everywhere on a plane).
RotationFit fit_rotation(const Eigen::Matrix3d& S, Eigen::Matrix3d& V, const Eigen::Matrix3d* near) {
  if (near) {
    RotationFit fit;
    fit.R = *near;
    if (refine_rotation(S, fit.R)) return fit;
  }
  Eigen::Matrix3d A = S * V;
  constexpr int kPairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
  // Jacobi converges quadratically: a sweep whose largest cosine was c leaves about c^2.
  // So a sweep that started below sqrt(kOrthogonal) is the last one, and no extra sweep is
  // spent only on checking.
  const double last_sweep_cosine = std::sqrt(kOrthogonal);
  for (int sweep = 0; sweep < 12; ++sweep) {
    double largest = 0.0;
    for (const auto& pair : kPairs) {
      const int p = pair[0], q = pair[1];
      const double alpha = A.col(p).squaredNorm(), beta = A.col(q).squaredNorm(), gamma = A.col(p).dot(A.col(q));
      const double scale = std::sqrt(alpha * beta);
      if (!(std::abs(gamma) > kOrthogonal * scale)) continue;
      largest = std::max(largest, std::abs(gamma) / scale);
      const double zeta = (beta - alpha) / (2.0 * gamma);
      const double t = (zeta >= 0.0 ? 1.0 : -1.0) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
      const double c = 1.0 / std::sqrt(1.0 + t * t), s = c * t;
      const Eigen::Vector3d ap = A.col(p), vp = V.col(p);
      A.col(p) = c * ap - s * A.col(q);
      A.col(q) = s * ap + c * A.col(q);
      V.col(p) = c * vp - s * V.col(q);
      V.col(q) = s * vp + c * V.col(q);
    }
    if (largest < last_sweep_cosine) break;
  }
  const Eigen::Vector3d sigma(A.col(0).norm(), A.col(1).norm(), A.col(2).norm());
  int i1 = 0;
  if (sigma(1) > sigma(i1)) i1 = 1;
  if (sigma(2) > sigma(i1)) i1 = 2;
  int i2 = (i1 == 0) ? 1 : 0;
  for (int k = 0; k < 3; ++k)
    if (k != i1 && sigma(k) > sigma(i2)) i2 = k;

  RotationFit fit;
  if (!(sigma(i1) > 0.0)) {
    fit.R.setIdentity();
    fit.u1 = fit.v1 = Eigen::Vector3d::UnitX();
    fit.degenerate = true;
    return fit;
  }
  fit.u1 = A.col(i1) / sigma(i1);
  fit.v1 = V.col(i1);
  if (sigma(i2) < kDegenerateRatio * sigma(i1)) {
    // u2 = a2 / sigma2 would be round-off amplified by sigma1 / sigma2: not to be trusted.
    fit.degenerate = true;
    fit.R = minimal_rotation(fit.u1, fit.v1);
    return fit;
  }
  Eigen::Vector3d u2 = A.col(i2) - fit.u1.dot(A.col(i2)) * fit.u1;  // re-orthogonalized
  u2.normalize();
  const Eigen::Vector3d v2 = V.col(i2);
  fit.R = fit.v1 * fit.u1.transpose() + v2 * u2.transpose() + fit.v1.cross(v2) * fit.u1.cross(u2).transpose();
  return fit;
}

Eigen::Matrix3d rotation_about_axis(const Eigen::Vector3d& u1, const Eigen::Vector3d& v1, const Eigen::Matrix3d& tie) {
  // R = Rot(v1, phi) R0 with R0 u1 = v1; trace(R tie) = a cos(phi) + b sin(phi) + const.
  const Eigen::Matrix3d R0 = minimal_rotation(u1, v1);
  const Eigen::Matrix3d N = R0 * tie;
  const double a = N.trace() - v1.dot(N * v1);
  const double b = v1.x() * (N(1, 2) - N(2, 1)) + v1.y() * (N(2, 0) - N(0, 2)) + v1.z() * (N(0, 1) - N(1, 0));
  if (std::hypot(a, b) <= 1e-14 * N.norm()) return R0;
  const double phi = std::atan2(b, a);
  const Eigen::Matrix3d K = cross_matrix(v1);
  const Eigen::Matrix3d rot = Eigen::Matrix3d::Identity() + std::sin(phi) * K + (1.0 - std::cos(phi)) * K * K;
  return rot * R0;
}

}  // namespace edgedeform
