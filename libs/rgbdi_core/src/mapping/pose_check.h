// Validity check of rigid transforms handed to the mapping stage.
#pragma once

#include <Eigen/Geometry>

namespace rgbdi::mapping::detail {

/// |R^T R - I| and |det R - 1| above this mean the matrix is not a rotation (numerical noise of
/// a composed or optimised pose stays orders of magnitude below).
inline constexpr double kRotationTolerance = 1e-6;

/// True when T is finite and its linear part is a proper rotation.
inline bool isRigid(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return false;
  const Eigen::Matrix3d R = T.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <
             kRotationTolerance &&
         std::abs(R.determinant() - 1.0) < kRotationTolerance;
}

}  // namespace rgbdi::mapping::detail
