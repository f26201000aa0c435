// The body's motion between two times from the buffered IMU samples: what the front end needs to
// predict where features move when the camera turns or moves fast.
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

/// The body's state at t0 in a gravity-aligned world frame: what dead reckoning starts from.
struct BodyState {
  Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();   ///< [m/s]
  Eigen::Vector3d bias_gyr = Eigen::Vector3d::Zero();  ///< [rad/s]
  Eigen::Vector3d bias_acc = Eigen::Vector3d::Zero();  ///< [m/s^2]
};

/// T_b0_b1: the body at t1 in the body frame at t0, dead-reckoned from `start` (its attitude and
/// velocity at t0) with the buffer's rates and specific forces minus the biases and gravity
/// `g_world` [m/s^2] (e.g. (0, 0, -9.81) in a z-up world); samples are taken as
/// gyroRotation takes them (mean of consecutive samples, the nearest one held outside the
/// buffered span). Identity when the buffer is empty or t1 <= t0. `end` (optional) receives the
/// state at t1 (attitude and velocity; the biases of `start`).
Eigen::Isometry3d deadReckonedMotion(const ImuBuffer& buffer, double t0, double t1,
                                     const BodyState& start, const Eigen::Vector3d& g_world,
                                     BodyState* end = nullptr);

/// [rad/s] The body's rate at t from the buffer minus `bias_gyr`: interpolated inside the
/// buffered span, the nearest sample's outside it (as gyroRotation holds it); zero when empty.
Eigen::Vector3d gyroRate(const ImuBuffer& buffer, double t, const Eigen::Vector3d& bias_gyr);

}  // namespace rgbdi::imu
