// Wheel-inertial dead reckoning across blind frames (doc/wheels.md "Blind frames"): from a
// window state at t0, the wheel frame advances by the odometry's increments (scaled by the
// learnt forward scale), each rotated into the world by the orientation the gyroscope
// integrates from t0 (so ramps and turns are followed in 3-D); the body follows through the
// extrinsic. Without vision the IMU alone drifts by its velocity error (metres in 10 s); the
// wheels hold the distance.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "estimator/window_wheels.h"
#include "rgbdi/common/types.h"

namespace rgbdi::estimator {

struct DeadReckoning {
  Eigen::Vector3d p_world_body = Eigen::Vector3d::Zero();  ///< [m] at t
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();       ///< [m/s] of the body at t
};

/// The body position and velocity at IMU-clock time t from the state (p0, q0) at t0; `imu`:
/// the samples between t0 and t; bg: gyroscope bias [rad/s]. nullopt when the readings do not
/// cover [t0, t - reading_lag_s] (the newest increment's velocity carries the rest).
std::optional<DeadReckoning> wheelInertialDeadReckoning(const WindowWheels& wheels,
                                                        const WheelOptions& opt,
                                                        const std::vector<ImuSample>& imu,
                                                        const Eigen::Vector3d& bg, double t0,
                                                        const Eigen::Vector3d& p0,
                                                        const Eigen::Quaterniond& q0, double t);

}  // namespace rgbdi::estimator
