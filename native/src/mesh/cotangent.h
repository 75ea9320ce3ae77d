// Cotangent of the angle between two vectors, finite for needle and zero-area triangles.
#pragma once

#include <algorithm>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace edgedeform {

// |u x v| is floored at kSinFloor * |u||v|, so |cot| <= 1/kSinFloor; a zero-length side
// gives 0 (the corner has no defined angle and contributes nothing).
constexpr double kSinFloor = 1e-6;

inline double safe_cotangent(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  const double lengths = u.norm() * v.norm();
  if (!(lengths > 0.0)) return 0.0;
  const double sine_area = u.cross(v).norm();
  return u.dot(v) / std::max(sine_area, kSinFloor * lengths);
}

}  // namespace edgedeform
