// The body's rotation between two times from the gyroscope alone: what the front end needs to
// predict where features move when the camera turns fast.
#pragma once

#include <Eigen/Geometry>

#include "rgbdi/imu/imu_buffer.h"

namespace rgbdi::imu {

/// R_b0_b1: the body frame at t1 expressed in the body frame at t0 [rad-consistent quaternion],
/// from the rates of `buffer` minus `bias_gyr` [rad/s], integrated between consecutive samples
/// at their mean rate (the buffered samples inside [t0, t1] plus interpolated ones at the ends).
/// Outside the buffered span (the newest image may arrive before the IMU samples that follow it)
/// the nearest sample's rate is held. Identity when the buffer is empty or t1 <= t0.
Eigen::Quaterniond gyroRotation(const ImuBuffer& buffer, double t0, double t1,
                                const Eigen::Vector3d& bias_gyr);

}  // namespace rgbdi::imu
