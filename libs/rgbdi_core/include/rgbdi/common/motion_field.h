// Image-plane velocity of a static point seen by a moving camera (the motion field): the
// estimator's time-offset and rolling-shutter shifts and the front end's depth reading use it.
//
// The time-offset correction of the reprojection factor needs each observation's image velocity.
// Differencing two tracked positions (what the reference does) correlates the velocity with the
// position noise of the same observation, and the optimiser then "explains" pixel noise with the
// time offset: with 0.5 px white tracking noise the estimate drifts by tens of milliseconds. The
// motion field computed from the gyro, the estimated velocity and the feature depth is independent
// of the pixel noise, so it does not bias the time offset.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace rgbdi {

/// d(xn)/dt [1/s] of a static point at normalised position xn and depth `depth_m` (along the
/// optical axis) for a camera with angular velocity omega_cam [rad/s] and linear velocity v_cam
/// [m/s], both expressed in the camera frame. depth_m <= 0 (unknown) gives the rotational part
/// only.
Eigen::Vector2d motionFieldVelocity(const Eigen::Vector2d& xn, double depth_m,
                                    const Eigen::Vector3d& omega_cam, const Eigen::Vector3d& v_cam);

/// The camera's motion in its own frame, for motionFieldVelocity.
struct CameraVelocity {
  Eigen::Vector3d omega_cam = Eigen::Vector3d::Zero();  ///< [rad/s]
  Eigen::Vector3d v_cam = Eigen::Vector3d::Zero();      ///< [m/s] of the camera centre
};
/// The camera's velocity from the body's: the body turning at omega_body [rad/s] and moving at
/// v_body [m/s], both in the body frame. The camera centre sits at the lever arm
/// T_body_cam.translation(), so it moves at v + omega x t_bc.
CameraVelocity cameraVelocity(const Eigen::Isometry3d& T_body_cam, const Eigen::Vector3d& v_body,
                              const Eigen::Vector3d& omega_body);

/// [m] The median of the positive depths (0 when there is none): the depth given to points whose
/// own depth is unknown (the translational term only needs a rough one).
double typicalDepth(std::vector<double> depths_m);

}  // namespace rgbdi
