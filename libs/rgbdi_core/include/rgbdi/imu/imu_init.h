// Helpers for the depth-aided initialisation: attitude from gravity and gyro bias from vision.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "rgbdi/imu/preintegration.h"

namespace rgbdi::imu {

/// R_world_body (as a quaternion) with roll and pitch such that the mean accelerometer reading
/// (specific force at rest, body frame; subtract a known accelerometer bias first) points along
/// world +z, and yaw zero. Throws std::invalid_argument for a zero or non-finite vector.
Eigen::Quaterniond gravityAlignedAttitude(const Eigen::Vector3d& mean_acc);

/// One interval for the gyro-bias solve: the relative rotation q_wb_i^-1 q_wb_j measured by vision
/// and the pre-integration over the same interval.
using GyroBiasPair = std::pair<Eigen::Quaterniond, const Preintegration*>;

/// Linear least squares for the gyro bias: J_theta_bg * dbg = Log(dq_ij^-1 q_ij_vision) stacked
/// over all pairs. Returns the CORRECTION to add to the linearisation gyro bias of the
/// pre-integrations (they should share it; otherwise the correction is relative to
/// pairs.front()'s). Throws std::invalid_argument for an empty list, a null pre-integration, or a
/// rank-deficient system.
Eigen::Vector3d solveGyroBias(const std::vector<GyroBiasPair>& pairs);

}  // namespace rgbdi::imu
