// Typed options of the sensor rig: [camera], [imu] and [extrinsic] sections of the config.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/rolling_shutter.h"

namespace rgbdi {

/// [camera]: colour camera intrinsics and where intrinsics come from.
struct CameraOptions {
  PinholeCamera camera;  ///< defaults: D435i colour camera, 640x480
  /// "stream": use the intrinsics carried by each observation when present (MRPT rawlogs carry
  /// them), falling back to the config; "config": always use the config values.
  std::string intrinsics_source = "stream";
  /// [s] rolling-shutter readout time of the colour camera: the rows are read top to bottom in
  /// this time and the image is stamped at its middle row (common/rolling_shutter.h); the
  /// estimator predicts each observation at its row's time. 0 = global shutter.
  double rolling_shutter_readout_s = 0.0;

  CameraOptions();
  /// The row timing of the colour images (top to bottom, stamped at the middle row).
  RollingShutter rollingShutter() const;
  static CameraOptions load(IniReader& ini);
};

/// [imu]: noise model (continuous-time densities, Kalibr convention) and gravity.
struct ImuOptions {
  double rate_hz = 200.0;              ///< nominal sample rate [Hz]
  double acc_noise_density = 0.005;    ///< [m/s^2/sqrt(Hz)]
  double gyr_noise_density = 0.0005;   ///< [rad/s/sqrt(Hz)]
  double acc_random_walk = 1.4142e-5;  ///< [m/s^3/sqrt(Hz)]
  double gyr_random_walk = 1.4142e-6;  ///< [rad/s^2/sqrt(Hz)]
  double gravity_m_s2 = 9.805;         ///< magnitude of gravity [m/s^2]

  static ImuOptions load(IniReader& ini);
};

/// [extrinsic]: the one source of the camera-IMU transform and time offset.
struct ExtrinsicOptions {
  /// Pose of the colour camera optical frame (x right, y down, z forward) in the IMU/body frame.
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  /// Time offset [s] with t_imu = t_cam + time_offset_s (VINS "td" convention).
  double time_offset_s = 0.0;
  /// Tolerances for warning about a rawlog sensorPose that disagrees with T_body_cam.
  double sensor_pose_tolerance_m = 0.01;
  double sensor_pose_tolerance_deg = 1.0;

  ExtrinsicOptions();
  static ExtrinsicOptions load(IniReader& ini);
};

}  // namespace rgbdi
