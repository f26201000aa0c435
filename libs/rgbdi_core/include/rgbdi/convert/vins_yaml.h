// VINS-Mono / VINS-RGBD calibration files (OpenCV FileStorage "%YAML:1.0"): reading them, and
// writing the same calibration as an rgbdi configuration ([camera] [imu] [extrinsic], the
// format of share/config.ini), so that a VINS-RGBD user keeps the calibration they have.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/sensor_options.h"

namespace rgbdi::convert {

/// The VINS noise values: white noise acc_n [m/s^2], gyr_n [rad/s] and bias random walk acc_w
/// [m/s^3], gyr_w [rad/s^2] as VINS uses them per IMU sample.
struct VinsImuNoise {
  double acc_n = 0.0, gyr_n = 0.0, acc_w = 0.0, gyr_w = 0.0;
};

struct VinsCalibration {
  std::string path;
  PinholeCamera camera;        ///< image_width/height, projection_parameters, distortion_parameters
  bool has_extrinsic = false;  ///< extrinsicRotation and extrinsicTranslation present
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();  ///< camera in the IMU frame
  Eigen::Matrix3d R_body_cam_as_given =
      Eigen::Matrix3d::Identity();  ///< before re-orthonormalising
  VinsImuNoise noise;
  double g_norm = 9.81;  ///< [m/s^2]
  double td = 0.0;       ///< [s] t_imu = t_cam + td
  /// [s] rolling-shutter readout: rolling_shutter_tr when rolling_shutter is 1; 0 (global
  /// shutter) when rolling_shutter is 0 or absent, as VINS-Mono reads them. VINS-Mono's model
  /// is rgbdi's (rows read top to bottom, stamped at the middle row).
  double rolling_shutter_readout_s = 0.0;
};

/// Reads a VINS yaml. Throws ConfigError naming the file and the key that is missing or invalid
/// (non-PINHOLE model_type, extrinsicRotation that is not a rotation, non-positive noise, ...).
VinsCalibration readVinsYaml(const std::string& path);

/// VINS per-sample noise -> continuous densities of [imu] at sample rate `rate_hz` (doc/imu.md):
///   acc_noise_density = acc_n * sqrt(dt / 2), gyr_noise_density = gyr_n * sqrt(dt / 2),
///   acc_random_walk = acc_w * sqrt(dt),       gyr_random_walk = gyr_w * sqrt(dt),  dt = 1/rate.
ImuOptions imuOptionsFromVins(const VinsImuNoise& noise, double g_norm, double rate_hz);

/// The inverse of imuOptionsFromVins: the VINS per-sample values of [imu] densities at the
/// sample rate imu.rate_hz (acc_n = nd / sqrt(dt / 2), acc_w = rw / sqrt(dt), dt = 1/rate).
VinsImuNoise vinsNoiseFromImuOptions(const ImuOptions& imu);

/// What a VINS-RGBD user has for a sensor: the calibration file (OpenCV "%YAML:1.0") of the
/// published dataset's layout, with the topics of that layout (SPEC section 6), the camera,
/// the extrinsic (camera in the IMU frame), the IMU noise of `imu` as VINS per-sample values
/// and `td` [s] (t_imu = t_cam + td); a `rolling_shutter_readout_s` [s] other than 0 is written
/// as rolling_shutter: 1 and rolling_shutter_tr (0: neither key, which VINS reads as a global
/// shutter). readVinsYaml reads it back to the same values (the numbers are written in
/// round-trip precision).
std::string vinsYamlText(const PinholeCamera& camera, const Eigen::Isometry3d& T_body_cam,
                         const ImuOptions& imu, double td, double rolling_shutter_readout_s = 0.0);

/// The rgbdi configuration text ([camera] [imu] [extrinsic]) for `v` with the IMU sampled at
/// `imu_rate_hz`; `rate_note` says where that rate comes from. The text is loaded back through
/// the option loaders before it is returned; throws ConfigError naming the yaml when a value is
/// outside what rgbdi accepts.
std::string rgbdiConfigFromVins(const VinsCalibration& v, double imu_rate_hz,
                                const std::string& rate_note);

}  // namespace rgbdi::convert
