// A wheel-odometry reading as sources deliver it (MRPT CObservationOdometry).
// Units: seconds, metres, radians.
#pragma once

#include <cmath>
#include <cstdint>

namespace rgbdi {

/// One wheel-odometry reading (MRPT CObservationOdometry): the cumulative planar pose of the
/// wheel frame (x forward, y left, z up; where it sits on the body is configuration) in its
/// odometry frame as the robot's own dead reckoning reports it, and what else the source has.
/// Sources give no covariance: the noise model is the consumer's.
struct WheelOdometrySample {
  double t = 0.0;        ///< [s]
  double x_m = 0.0;      ///< [m] cumulative position in the odometry frame
  double y_m = 0.0;      ///< [m]
  double yaw_rad = 0.0;  ///< [rad] cumulative heading in the odometry frame
  bool has_velocities = false;
  double v_forward_m_s = 0.0;   ///< [m/s] along the wheel frame's x (has_velocities)
  double v_lateral_m_s = 0.0;   ///< [m/s] along its y (has_velocities)
  double yaw_rate_rad_s = 0.0;  ///< [rad/s] about its z (has_velocities)
  bool has_encoders = false;
  std::int32_t ticks_left = 0;   ///< cumulative encoder count, positive forward (has_encoders)
  std::int32_t ticks_right = 0;  ///< cumulative encoder count, positive forward (has_encoders)
};

/// Whether every value of the reading (pose, velocities) is finite.
inline bool isFinite(const WheelOdometrySample& w) {
  return std::isfinite(w.t) && std::isfinite(w.x_m) && std::isfinite(w.y_m) &&
         std::isfinite(w.yaw_rad) && std::isfinite(w.v_forward_m_s) &&
         std::isfinite(w.v_lateral_m_s) && std::isfinite(w.yaw_rate_rad_s);
}

/// The reading's heading unwrapped against `ref_rad` (sources wrap it at +-pi): the angle equal
/// to it modulo 2 pi nearest to `ref_rad`.
inline double unwrappedYaw(const WheelOdometrySample& w, double ref_rad) {
  return ref_rad + std::remainder(w.yaw_rad - ref_rad, 2.0 * M_PI);
}

}  // namespace rgbdi
