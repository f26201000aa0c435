// IMU noise model used by pre-integration: continuous-time densities (Kalibr convention).
#pragma once

#include "rgbdi/common/sensor_options.h"

namespace rgbdi::imu {

/// Continuous-time noise densities of the IMU (see doc/imu.md for the discretisation and for
/// the mapping of VINS yaml values acc_n, gyr_n, acc_w, gyr_w onto these).
struct ImuNoise {
  double acc_nd = 0.0;  ///< accelerometer white noise [m/s^2/sqrt(Hz)]
  double gyr_nd = 0.0;  ///< gyroscope white noise [rad/s/sqrt(Hz)]
  double acc_rw = 0.0;  ///< accelerometer bias random walk [m/s^3/sqrt(Hz)]
  double gyr_rw = 0.0;  ///< gyroscope bias random walk [rad/s^2/sqrt(Hz)]

  static ImuNoise fromOptions(const ImuOptions& options);
};

}  // namespace rgbdi::imu
