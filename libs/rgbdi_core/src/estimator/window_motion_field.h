// Image velocities of a window slot's observations from that slot's state (the motion field of
// motion_field.h), for the time-offset correction of the reprojection factors: independent of
// the pixel noise, unlike the difference of two tracked positions (doc/estimator.md "Time
// offset").
#pragma once

#include <Eigen/Geometry>
#include <cstddef>

namespace rgbdi::imu {
class ImuBuffer;
}

namespace rgbdi::estimator {

class FrameWindow;

/// Replaces the image velocities of the observations in window slot `slot` by the motion field
/// of its state (angular rate from `imu` at the slot's time, less the gyro bias); no-op when
/// `imu` does not cover that time.
void assignMotionFieldVelocities(FrameWindow& window, std::size_t slot, const imu::ImuBuffer& imu,
                                 const Eigen::Isometry3d& T_body_cam);

}  // namespace rgbdi::estimator
