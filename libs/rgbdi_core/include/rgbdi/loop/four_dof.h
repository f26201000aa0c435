// 4-DOF pose algebra of the loop-closure pose graph. Gravity makes roll and pitch observable, so
// the odometry drifts only in x, y, z and yaw: a body rotation is split as
// R = Rz(yaw) * R_tilt (ZYX Euler angles, R_tilt = Ry(pitch) * Rx(roll)) and only yaw is
// estimated. A relative pose between keyframes i and j is kept as the translation expressed in
// i's yaw-only frame (origin at i, axes rotated by yaw_i about z) and the yaw difference.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace rgbdi::loop {

/// Heading of a body rotation (ZYX yaw): angle of its x axis projected on the horizontal plane.
inline double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

/// Rotation by `yaw` [rad] about the world z axis.
inline Eigen::Matrix3d rotZ(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// Roll/pitch part of R: Rz(-yawOf(R)) * R, so that R == rotZ(yawOf(R)) * tiltOf(R).
inline Eigen::Matrix3d tiltOf(const Eigen::Matrix3d& R) { return rotZ(-yawOf(R)) * R; }

/// A relative pose reduced to 4 DOF.
struct FourDofDelta {
  Eigen::Vector3d t_m = Eigen::Vector3d::Zero();  ///< [m] in the `from` node's yaw-only frame
  double yaw_rad = 0.0;                           ///< [rad] yaw_to - yaw_from, in [-pi, pi)
};

/// Reduces the body-frame relative pose T_from_to to 4 DOF, given the roll/pitch part of the
/// `from` body rotation. Exact: for T_from_to = T_w_from^-1 * T_w_to the result equals
/// (Rz(yaw_from)^T (t_to - t_from), yaw_to - yaw_from) whatever the roll/pitch of both.
FourDofDelta fourDofDelta(const Eigen::Matrix3d& R_tilt_from, const Eigen::Isometry3d& T_from_to);

/// The 4-DOF correction T_a * T_b^-1 of two poses with the same roll/pitch: rotation about z by
/// the yaw difference and a translation (the tilt cancels).
Eigen::Isometry3d fourDofCorrection(const Eigen::Vector3d& t_a, double yaw_a,
                                    const Eigen::Vector3d& t_b, double yaw_b);

}  // namespace rgbdi::loop
