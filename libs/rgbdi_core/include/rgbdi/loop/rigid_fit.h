// Weighted least-squares rigid transform between two point sets (Horn / Umeyama without scale):
// the rotation from the SVD of the weighted cross-covariance, with the reflection fix.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace rgbdi::loop {

/// T minimising sum_i w_i |T * src_i - dst_i|^2. Needs >= 3 non-collinear points with positive
/// weights; returns false (T untouched) for fewer points, non-positive total weight or a
/// degenerate (collinear) configuration.
bool fitRigidWeighted(const std::vector<Eigen::Vector3d>& src,
                      const std::vector<Eigen::Vector3d>& dst, const std::vector<double>& weights,
                      Eigen::Isometry3d& T_dst_src);

/// A 3-D point measured by an RGB-D camera: its position in that camera's frame and the
/// standard deviations of the measurement across the viewing ray (pixel noise times range) and
/// along it (depth noise).
struct RgbdPoint {
  Eigen::Vector3d p;
  double sigma_lateral_m = 0.0;
  double sigma_ray_m = 0.0;
};

/// The covariance of an RgbdPoint: sigma_ray^2 along p's direction, sigma_lateral^2 across it.
Eigen::Matrix3d rgbdPointCovariance(const RgbdPoint& point);

/// Refines T_dst_src (in place) by Gauss-Newton on sum_i r_i^T (C_dst_i + R C_src_i R^T)^-1 r_i,
/// r_i = T * src_i - dst_i: the maximum-likelihood rigid transform between two sets of RGB-D
/// points whose noise is anisotropic. A depth camera's points are far less certain along the
/// ray (D435: 0.004 z^2, 3.6 cm at 3 m) than across it (1 px: 6.5 mm at 3 m), which an
/// isotropic fit ignores: it lets the depth noise of far points move the pose. With precise depth
/// this is the 3-D/3-D fit; with noisy depth it approaches the reprojection error both ways.
/// Returns false (T untouched) for fewer than 3 pairs, sizes that differ or a singular system.
bool refineRigidAnisotropic(const std::vector<RgbdPoint>& src, const std::vector<RgbdPoint>& dst,
                            int iterations, Eigen::Isometry3d& T_dst_src);

}  // namespace rgbdi::loop
