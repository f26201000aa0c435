// Depth-aided visual-inertial initialisation (paper section 4.2) and static initialisation.
//
// Moving start: metric relative camera poses come from PnP RANSAC on depth-backed points, so no
// scale unknown remains; the gyro bias comes from the rotations, then one linear solve gives the
// velocities and gravity, and gravity is refined on its 2-DOF tangent space with known magnitude.
// Static start: gravity from the mean accelerometer, zero velocity, gyro bias from the mean gyro.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "rgbdi/common/types.h"

namespace rgbdi::imu {
class Preintegration;
}

namespace rgbdi::estimator {

struct PnpOptions {
  int min_inliers = 20;                        ///< inlier count needed to accept the pose
  double ransac_threshold_norm = 3.0 / 460.0;  ///< reprojection threshold on the normalised plane
  int ransac_iterations = 100;
  std::uint64_t seed = 1;  ///< RANSAC sampling is made deterministic
};

struct PnpResult {
  Eigen::Isometry3d T_curr_prev = Eigen::Isometry3d::Identity();  ///< maps prev-camera points
  int inliers = 0;
  std::vector<int> inlier_indices;
};

/// Relative pose of the current camera from 3-D points in the previous camera (from depth) and
/// their normalised observations in the current image. The rotation vector is turned into a
/// matrix by the exponential map (cv::Rodrigues). Returns nullopt when RANSAC fails or the inlier
/// count is below min_inliers.
std::optional<PnpResult> relativePoseByPnP(const std::vector<Eigen::Vector3d>& pts_prev_cam,
                                           const std::vector<Eigen::Vector2d>& xn_curr,
                                           const PnpOptions& opt);

/// Gravity-aligned attitude R_world_body from a mean specific force (body frame) with the given
/// yaw [rad] (rotation about world z).
Eigen::Matrix3d attitudeFromGravity(const Eigen::Vector3d& mean_acc_body, double yaw);

/// Result of the linear alignment.
struct AlignmentResult {
  std::vector<Eigen::Vector3d> v_ref;  ///< velocity of every frame in the reference frame
  Eigen::Vector3d g_ref;               ///< gravity vector in the reference frame (|g| = g_norm)
  double residual_rms = 0.0;           ///< RMS of the linear system's residual
};

/// Paper eq. (19)-(20) + gravity refinement: given metric body poses T_ref_body of frames 0..n
/// (expressed in any reference frame, e.g. the first camera) and the pre-integrations between
/// consecutive frames (preint[k] integrates frame k-1 -> k; preint[0] is unused), solve the
/// velocities and gravity. Returns nullopt when the system is degenerate.
std::optional<AlignmentResult> alignVelocitiesAndGravity(
    const std::vector<Eigen::Isometry3d>& T_ref_body,
    const std::vector<const imu::Preintegration*>& preint, double g_norm);

/// Rotation R_world_ref that maps the gravity direction onto world -z, choosing the rotation about
/// world z so that body frame `T_ref_body0` gets yaw `yaw0`.
Eigen::Matrix3d worldFromGravity(const Eigen::Vector3d& g_ref, const Eigen::Matrix3d& R_ref_body0,
                                 double yaw0);

/// Yaw of a rotation (ZYX convention, rotation about world z).
double yawOf(const Eigen::Matrix3d& R_world_body);

}  // namespace rgbdi::estimator
