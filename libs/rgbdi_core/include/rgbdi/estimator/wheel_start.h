// A start from the wheels (doc/wheels.md "Start from the wheels"): the wheel odometry gives the
// body's velocity at any time (forward speed along the wheel frame, through the extrinsic), so
// over a short window the IMU's velocity change minus the wheels' one is gravity, whatever the
// motion: standing, cruising, turning, on a ramp. With it the first frame that sees gets its
// attitude, velocity and gyroscope bias at once, as a resting sensor gets them from the static
// start, instead of waiting for the frames and the parallax of a moving start.
//
// Over the window [t_e - W, t_e] (W = [wheel] start_window_s, t_e the newest reading's IMU-clock
// time, at most reading_lag_s before the frame) the wheels' mean velocity over a span of W/4 at
// each end and in the middle gives the body velocity v_a, v_c, v_b (body frame) at the spans'
// midpoints a, c, b: v = s_v R_body_wheel [dx; dy; 0] / dt - omega x p_body_wheel, with [dx; dy]
// the odometry's displacement over the span in the wheel frame at its middle and omega the gyro
// rate minus the bias. The gyroscope bias is the mean gyro rate over [a, b] minus the wheels' yaw
// rate (about the wheel frame's z, times s_w). With the IMU pre-integrated from a to b (dR, dv,
// that bias), v_b = v_a + g T + dv in the world, so gravity in the body frame at a is
//   g_a = (dR v_b - v_a - dv) / T.
// Checks (the wheels may slip, be stuck, be lifted at the start): the gyro rate the wheels' yaw
// rate does not explain (|bias|) at most start_max_rate_dev_rad_s; gravity from [a, c] and from
// [c, b] agreeing, and |g_a| equal to g, within start_max_gravity_dev_m_s2. The state at the
// frame's time t follows from b by the IMU.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <optional>

#include "rgbdi/common/wheel_odometry.h"
#include "rgbdi/estimator/wheel_options.h"

namespace rgbdi::imu {
class ImuBuffer;
}

namespace rgbdi::estimator {

/// The body's state at the frame from the wheels and the IMU, or why there is none.
struct WheelStart {
  const char* failure = nullptr;  ///< why not (a string literal); null when solved
  /// [m/s^2] the specific force of a body at rest in the body frame at t (minus gravity: "up"
  /// times g), what the static start takes from the mean accelerometer.
  Eigen::Vector3d up_body = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_body = Eigen::Vector3d::Zero();  ///< [m/s] velocity at t, body frame
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();      ///< [rad/s] gyroscope bias

  static WheelStart failed(const char* why) {
    WheelStart s;
    s.failure = why;
    return s;
  }
};

/// The start at IMU-clock time `t` from the readings (robot clock, time order) and the IMU
/// (covering [t - start_window_s - reading_lag_s, t]); `calib`: the odometry's calibration in
/// effect (scales, extrinsic, time offset); `gravity_m_s2`: |g|; `opt`: the start's limits.
WheelStart solveWheelStart(const std::deque<WheelOdometrySample>& readings,
                           const WheelCalibration& calib, const imu::ImuBuffer& imu, double t,
                           double gravity_m_s2, const WheelOptions& opt);

/// The same window's gravity with a known gyroscope bias `bg` (the window's), for the ground
/// plane's gate (doc/wheels.md "Ground plane"): "up" times g in the body frame at t (as
/// WheelStart::up_body), whatever the motion and whatever the window's states say; nullopt when
/// the readings or the IMU do not cover the window or |gravity| differs from g by more than
/// start_max_gravity_dev_m_s2 (slip, a bump's shock).
std::optional<Eigen::Vector3d> wheelInertialUp(const std::deque<WheelOdometrySample>& readings,
                                               const WheelCalibration& calib,
                                               const imu::ImuBuffer& imu, double t,
                                               const Eigen::Vector3d& bg, double gravity_m_s2,
                                               const WheelOptions& opt);

}  // namespace rgbdi::estimator
