// Options of the measurement stream ([stream] section) and the bundle of everything a source
// needs to order and check a stream (stream + [imu] rate/gravity + [extrinsic] camera pose).
#pragma once

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"

namespace rgbdi::io {

/// [stream]: ordering windows and the thresholds of the data checks.
struct StreamOptions {
  double imu_reorder_window_s = 0.05;    ///< [s] late IMU samples within this are reordered
  double image_reorder_window_s = 0.1;   ///< [s] same for RGB-D frames (also cross-kind lateness)
  double imu_gap_factor = 3.0;           ///< gap when dt > factor / [imu] rate_hz
  double image_gap_factor = 2.5;         ///< gap when dt > factor * median frame period
  double imu_rate_tolerance = 0.2;       ///< warn when measured rate deviates more (fraction)
  double g_units_min_m_s2 = 0.5;         ///< [m/s^2] mean |acc| in [min, max] looks like g units
  double g_units_max_m_s2 = 2.0;         ///< [m/s^2]
  double acc_magnitude_tolerance = 0.5;  ///< warn when mean |acc| deviates from g more (fraction)
  double depth_median_min_m = 0.05;      ///< [m] lower median valid depth: unit suspected wrong
  double depth_median_max_m = 20.0;      ///< [m] higher median valid depth: unit suspected wrong
  int depth_check_step_px = 4;           ///< [px] sampling step of the per-frame depth median
  int max_listed_issues = 10;            ///< messages per kind of issue; further ones only counted
  double accel_scale = 1.0;              ///< [(m/s^2) per recorded unit] 9.80665 for data in g
  int accel_check_samples = 100;         ///< [count] IMU samples averaged before the unit check
  double accel_check_max_s = 2.0;        ///< [s] or the samples of the first this much data
  double time_jump_back_s = 0.5;         ///< [s] a stamp this much older than the newest: stop
  int constant_image_max_range = 2;      ///< [grey levels] max - min at most this: constant image
  int image_check_step_px = 8;           ///< [px] pixel step of the constant-image sampling
  /// [Hz] RGB-D frames used per second at most (FrameRateLimiter); 0 = every frame.
  double image_rate_limit_hz = 0.0;
  double wheel_gap_factor = 2.5;  ///< wheel-odometry gap when dt > factor * its median period
  /// The check "wheel odometry moves while the IMU is at rest" (a slipping or lifted wheel, a
  /// stream of another robot): over each window of this length the IMU is at rest when the norm
  /// of its mean angular rate and the standard deviation of |acc| are below the limits, and the
  /// wheels move when their mean speed or yaw rate over the window is above theirs.
  double wheel_rest_window_s = 1.0;         ///< [s]
  double wheel_rest_gyr_rad_s = 0.02;       ///< [rad/s]
  double wheel_rest_acc_std_m_s2 = 0.05;    ///< [m/s^2]
  double wheel_rest_speed_m_s = 0.05;       ///< [m/s]
  double wheel_rest_yaw_rate_rad_s = 0.05;  ///< [rad/s]
  /// The converse check "the wheels stand while the IMU moves" (a blocked wheel, a robot pushed
  /// or carried): over the same windows the IMU moves when the norm of its mean angular rate is
  /// above wheel_still_gyr_rad_s, or the accelerometer changes: the standard deviation of the
  /// means of the acceleration vector over blocks of wheel_still_block_s (block means, so that
  /// sensor noise and motor vibration average out) is above wheel_still_acc_m_s2; the wheels
  /// stand when they do not move (above).
  double wheel_still_gyr_rad_s = 0.1;  ///< [rad/s]
  double wheel_still_acc_m_s2 = 0.5;   ///< [m/s^2]
  double wheel_still_block_s = 0.1;    ///< [s]

  static StreamOptions load(IniReader& ini);
};

/// Everything a measurement source needs from the configuration.
struct StreamConfig {
  StreamOptions stream;
  ImuOptions imu;              ///< rate_hz (gap threshold) and gravity_m_s2 (unit check)
  ExtrinsicOptions extrinsic;  ///< T_body_cam and tolerances (sensorPose check)
  /// Not from the INI: true for inspection (`rawlog-convert --info`): an accelerometer that looks
  /// like g units is reported but the stream is read to the end instead of being refused.
  bool report_only = false;

  static StreamConfig load(IniReader& ini);
};

}  // namespace rgbdi::io
