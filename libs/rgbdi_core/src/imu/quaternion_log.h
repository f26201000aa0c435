// Private helper of the imu stage: SO(3) logarithm taken directly from a unit quaternion (avoids
// the round trip through a rotation matrix, which costs precision in numeric Jacobian checks).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace rgbdi::imu::detail {

/// Rotation vector of q with angle in [0, pi] (q and -q give the same result).
inline Eigen::Vector3d logQuat(const Eigen::Quaterniond& q) {
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d v = sign * q.vec();
  const double w = sign * q.w();
  const double n = v.norm();
  // atan2(n, w) / n -> 1 / w as n -> 0, which is also the exact limit at n == 0.
  const double scale = n > 0.0 ? 2.0 * std::atan2(n, w) / n : 2.0 / w;
  return scale * v;
}

}  // namespace rgbdi::imu::detail
