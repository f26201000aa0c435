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

}  // namespace rgbdi::loop
