#include "rgbdi/imu/imu_init.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "imu/quaternion_log.h"

namespace rgbdi::imu {

Eigen::Quaterniond gravityAlignedAttitude(const Eigen::Vector3d& mean_acc) {
  const double n = mean_acc.norm();
  if (!mean_acc.allFinite() || !(n > 0.0))
    throw std::invalid_argument(
        "gravityAlignedAttitude: mean accelerometer vector must be finite and non-zero");
  // At rest the accelerometer measures R_wb^T (0, 0, g): the body-frame "up" direction.
  const Eigen::Quaterniond q_tilt =
      Eigen::Quaterniond::FromTwoVectors(mean_acc / n, Eigen::Vector3d::UnitZ());
  // Remove the yaw (rotation about world z leaves the up direction unchanged).
  const Eigen::Matrix3d R = q_tilt.toRotationMatrix();
  const double yaw = std::atan2(R(1, 0), R(0, 0));
  const Eigen::Quaterniond q_unyaw(Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()));
  return (q_unyaw * q_tilt).normalized();
}

Eigen::Vector3d solveGyroBias(const std::vector<GyroBiasPair>& pairs) {
  if (pairs.empty()) throw std::invalid_argument("solveGyroBias: no intervals given");
  // Unknown: the absolute bias b; each interval gives J_k (b - b_lin_k) = Log(dq_k^-1 q_vis_k).
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Preintegration* pre = pairs[k].second;
    if (pre == nullptr)
      throw std::invalid_argument("solveGyroBias: interval " + std::to_string(k) +
                                  " has a null pre-integration");
    const Eigen::Matrix3d Jk = pre->jacobian().block<3, 3>(kIdxR, kIdxBg);
    const Eigen::Vector3d rk =
        detail::logQuat(pre->deltaQ().inverse() * pairs[k].first.normalized());
    A += Jk.transpose() * Jk;
    rhs += Jk.transpose() * (rk + Jk * pre->biasGyr());
  }
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(A);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || ldlt.vectorD().minCoeff() <= 0.0)
    throw std::invalid_argument(
        "solveGyroBias: the rotation intervals do not constrain the gyro bias (zero duration?)");
  const Eigen::Vector3d bias = ldlt.solve(rhs);
  return bias - pairs.front().second->biasGyr();
}

}  // namespace rgbdi::imu
