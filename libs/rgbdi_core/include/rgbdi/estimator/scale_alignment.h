// Visual-inertial alignment of an up-to-scale SfM window (visual_sfm.h) with the IMU
// pre-integrations: gyro bias, metric scale, gravity and velocities, for starting without depth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

namespace rgbdi::imu {
class Preintegration;
}

namespace rgbdi::estimator {

struct ScaleAlignmentResult {
  double scale = 0.0;                  ///< metric = scale * SfM units
  std::vector<Eigen::Vector3d> v_ref;  ///< body velocities in the reference (c0) frame [m/s]
  Eigen::Vector3d g_ref = Eigen::Vector3d::Zero();  ///< gravity in c0, |g_ref| = g_norm [m/s^2]
  /// Gyro-bias correction found, relative to preint[1]'s linearisation bias; the new bias is
  /// already applied to every pre-integration by repropagate() (acc bias reset to 0).
  Eigen::Vector3d bg_correction = Eigen::Vector3d::Zero();
  /// RMS of the final whitened residual (dimensionless). Whenever the IMU noise alone cannot
  /// explain the residual, camera_position_sigma_m is raised until chi2 = degrees of freedom,
  /// which pins this to sqrt(dof / rows) (~0.6); it is lower only for near-exact data.
  double residual_rms = 0.0;
  /// Per-axis noise of the SfM camera positions [m] estimated from the residual (0 when the IMU
  /// noise model already explains it). A large value flags inconsistent vision and IMU data.
  double camera_position_sigma_m = 0.0;
  /// Predicted 1-sigma relative error of `scale` (generalised least squares covariance, with the
  /// IMU noise and the estimated camera-position noise). Large when the window lacks changes of
  /// acceleration: static or constant-velocity windows leave the scale unobservable.
  double scale_rel_sigma = 0.0;
};

/// Steps: (1) gyro bias from the visual rotations R_c0_bk = R_c0_ck R_cam_body
/// (imu::solveGyroBias, two Gauss-Newton passes, repropagating all pre-integrations with it and
/// zero acc bias); (2) generalised least squares for [v_0..v_n, g, s] with the body positions
/// p_c0_bk = s p_c0_ck - R_c0_bk p_body_cam (from T_c0_bk = T_c0_ck T_cam_body; the lever arm is
/// metric); (3) four refinements of g on its 2-DOF tangent space with |g| = g_norm, re-solving v
/// and s.
/// Weighting: each interval's [dp, dv] rows carry the pre-integration covariance plus the noise
/// of the camera positions, whose variance is chosen so that chi2 equals the degrees of freedom
/// (see camera_position_sigma_m). Weighting by the IMU noise alone would trust the position rows
/// blindly, and the SfM noise in them, multiplied by s, would pull the scale towards zero;
/// unweighted rows mix m and m/s arbitrarily.
///
/// T_c0_c: SfM camera poses (any common scale); T_body_cam: camera pose in the body (IMU) frame;
/// preint[k] integrates frame k-1 -> k (preint[0] unused, may be null); g_norm: |g| [m/s^2];
/// max_scale_rel_sigma: largest accepted scale_rel_sigma.
/// Returns nullopt when: fewer than 4 frames (6 (n - 1) equations for 3 n + 4 unknowns: three
/// frames are one short); mismatched sizes; a null or empty pre-integration; the gyro-bias solve
/// fails; the column-scaled system is rank-deficient (e.g. constant velocity); |g| of the
/// unconstrained solve is off by more than 25 %; scale <= 0 or non-finite results; or
/// scale_rel_sigma > max_scale_rel_sigma (a static window: the scale is unobservable and comes out
/// ~0). The pre-integrations stay repropagated with the new gyro bias even when nullopt is returned
/// after step (1).
std::optional<ScaleAlignmentResult> alignWithScale(const std::vector<Eigen::Isometry3d>& T_c0_c,
                                                   const Eigen::Isometry3d& T_body_cam,
                                                   const std::vector<imu::Preintegration*>& preint,
                                                   double g_norm, double max_scale_rel_sigma = 0.1);

}  // namespace rgbdi::estimator
