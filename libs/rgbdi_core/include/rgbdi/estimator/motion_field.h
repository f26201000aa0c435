// Image-plane velocity of a static point seen by a moving camera (the motion field).
//
// The time-offset correction of the reprojection factor needs each observation's image velocity.
// Differencing two tracked positions (what the reference does) correlates the velocity with the
// position noise of the same observation, and the optimiser then "explains" pixel noise with the
// time offset: with 0.5 px white tracking noise the estimate drifts by tens of milliseconds. The
// motion field computed from the gyro, the estimated velocity and the feature depth is independent
// of the pixel noise, so it does not bias the time offset.
#pragma once

#include <Eigen/Core>

namespace rgbdi::estimator {

/// d(xn)/dt [1/s] of a static point at normalised position xn and depth `depth_m` (along the
/// optical axis) for a camera with angular velocity omega_cam [rad/s] and linear velocity v_cam
/// [m/s], both expressed in the camera frame. depth_m <= 0 (unknown) gives the rotational part
/// only.
Eigen::Vector2d motionFieldVelocity(const Eigen::Vector2d& xn, double depth_m,
                                    const Eigen::Vector3d& omega_cam, const Eigen::Vector3d& v_cam);

}  // namespace rgbdi::estimator
