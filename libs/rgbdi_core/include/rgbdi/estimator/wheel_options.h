// Options of the wheel odometry in the odometry ([wheel] section, doc/wheels.md).
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {

struct WheelOptions {
  /// Fuse the wheel odometry of the input into the sliding window (false: it is ignored, and
  /// the run is what it is without it; rgbdi-slam --no-wheels sets it false).
  bool enable = false;
  double time_offset_s = 0.0;  ///< [s] t_imu = t_wheel + this
  /// Pose of the wheel frame (x forward, y left, z up, on the axle) in the body (IMU) frame.
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  WheelNoise noise;  ///< forward/lateral/vertical/yaw/tilt sigmas and their floors
  /// Estimate the forward-speed and yaw-rate scale factors of the odometry online.
  bool estimate_scale = true;
  /// [unitless] sigma of the prior that holds each scale factor at 1 until the marginalisation
  /// prior carries what the window learnt about it.
  double scale_prior_sigma = 0.05;
  /// Estimate a correction to the extrinsic's yaw about the wheel frame's z online
  /// (R_body_wheel = configured * Rz(correction)), doc/wheels.md "Online calibration".
  bool estimate_extrinsic_yaw = false;
  /// [rad] sigma of the prior holding that correction at 0 until the marginalisation prior
  /// carries what the window learnt about it.
  double extrinsic_yaw_prior_sigma_rad = 0.2;
  /// [rad] bound of |correction|: the estimate is clamped to it after every solve.
  double extrinsic_yaw_max_rad = 0.5;
  /// Estimate the wheel time offset (time_offset_s is then its prior mean and starting value).
  bool estimate_time_offset = false;
  /// [s] sigma of its prior around time_offset_s.
  double time_offset_prior_sigma_s = 0.1;
  /// [s] bound of |estimate - time_offset_s|: clamped after every solve.
  double time_offset_max_change_s = 0.3;
  /// [unitless] an interval whose wheel factor, at the window's states of its two frames (what
  /// the IMU and vision say), has a squared normalised error above this is left out (slip, a
  /// stuck wheel, a lifted robot); 0 = every interval is used.
  double gate_chi2 = 30.0;
  /// [s] with the wheels fused and their readings up to the frame, blind frames (a blackout, a
  /// bare wall, blur) are carried by the gyroscope and the wheels for up to this long before
  /// tracking is lost ([estimator] fail_max_blind_s otherwise); their positions come from the
  /// wheels, and the first frame that sees again starts from them.
  double max_blind_s = 10.0;
  /// [s] ... while the newest reading is at most this much older than the frame (readings come
  /// at their own rate: the frame's newest one is up to a period old).
  double reading_lag_s = 0.1;
  /// [unitless] a left-out interval is "stuck" when the wheels report less than this fraction
  /// of the distance the window moved, "lifted" when the window moved less than this fraction
  /// of what the wheels report, "slip" otherwise.
  double fault_motion_ratio = 0.25;
  /// Which intervals take the direction of travel (yaw and tilt) from the gyroscope, the wheel
  /// factor then 3-D (WheelPreintegration): "never" (planar in the wheel frame at the older
  /// frame), "blind" (intervals across blind frames: metres in which a ramp breaks the plane),
  /// "always" (also skid steering: the tracks' yaw slips in every turn).
  std::string direction_from_gyro = "blind";
  /// [m] soft ground-plane constraint of a flat-floor robot: every window frame found on the
  /// floor (ground_plane_gate.h) holds its wheel frame on that horizontal plane with this sigma on
  /// its height (0 = off).
  double ground_plane_sigma_m = 0.01;
  /// [rad] ... and this one on its tilt (roll, pitch).
  double ground_plane_tilt_sigma_rad = 0.02;
  /// [unitless] a frame whose state is farther from the plane than this squared Mahalanobis
  /// distance (3 dof) gets no constraint in that update: ramps, bumps, steps switch it off.
  double ground_plane_gate_chi2 = 11.3;
  /// Start from the wheels (rgbdi/estimator/wheel_start.h): the first frame that sees gets its
  /// attitude, velocity and gyroscope bias from the wheels and the IMU over the last
  /// start_window_s when the static start cannot start (the body moves, or vibrates).
  bool start_from_wheels = true;
  /// [s] the window of wheel readings and IMU samples the start uses.
  double start_window_s = 0.4;
  /// [m/s^2] gravity from the window's two halves may differ by this, and |gravity| from g.
  double start_max_gravity_dev_m_s2 = 0.3;
  /// [rad/s] gyro rate the wheels' yaw rate does not explain (the bias, or slip) at most this.
  double start_max_rate_dev_rad_s = 0.03;
  /// [m/s] prior sigma of the start's velocity (the wheels' speed).
  double start_velocity_sigma_m_s = 0.05;

  /// True when the extrinsic yaw or the time offset is estimated (WheelCalibrationFactor).
  bool calibrating() const { return estimate_extrinsic_yaw || estimate_time_offset; }

  /// Reads [wheel]; throws ConfigError on a value out of range or a matrix that is no rotation.
  static WheelOptions load(IniReader& ini);
};

/// The wheel odometry's calibration in effect: the scales (true = scale x reported) and the
/// extrinsic and time offset as learnt online, the configured ones when not estimated. Whatever
/// reads the odometry outside the factors (the start from the wheels, the ground plane's gate)
/// takes it, so it agrees with the factors after a reset that keeps the learnt calibration.
struct WheelCalibration {
  double scale_v = 1.0, scale_w = 1.0;
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  double time_offset_s = 0.0;  ///< [s] t_imu = t_wheel + this

  /// The configured calibration, scales 1.
  static WheelCalibration configured(const WheelOptions& opt) {
    WheelCalibration c;
    c.T_body_wheel = opt.T_body_wheel;
    c.time_offset_s = opt.time_offset_s;
    return c;
  }
};

}  // namespace rgbdi::estimator
