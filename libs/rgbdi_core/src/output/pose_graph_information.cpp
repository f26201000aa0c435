#include "rgbdi/output/pose_graph_information.h"

#include <mrpt/poses/CPose3D.h>

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rgbdi::output {

Eigen::Matrix3d yawPitchRollToRotationVectorJacobian(double pitch, double roll) {
  // Body-frame angular velocity of R = Rz(yaw) Ry(pitch) Rx(roll):
  //   w = Rx^T Ry^T e_z yaw' + Rx^T e_y pitch' + e_x roll'.
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  const double sr = std::sin(roll), cr = std::cos(roll);
  Eigen::Matrix3d E;
  E << -sp, 0.0, 1.0,    //
      cp * sr, cr, 0.0,  //
      cp * cr, -sr, 0.0;
  return E;
}

Eigen::Vector3d mrptYawPitchRoll(const Eigen::Matrix3d& R) {
  mrpt::math::CVectorFixedDouble<3> no_translation;
  no_translation.setZero();
  const mrpt::poses::CPose3D pose(mrpt::math::CMatrixDouble33(R), no_translation);
  double yaw = 0.0, pitch = 0.0, roll = 0.0;
  pose.getYawPitchRoll(yaw, pitch, roll);
  return {yaw, pitch, roll};
}

namespace {
Matrix6d blockJacobian(const Eigen::Matrix3d& R) {
  const Eigen::Vector3d ypr = mrptYawPitchRoll(R);
  Matrix6d B = Matrix6d::Identity();
  B.bottomRightCorner<3, 3>() = yawPitchRollToRotationVectorJacobian(ypr(1), ypr(2));
  return B;
}
}  // namespace

Matrix6d informationToMrpt(const Matrix6d& info, const Eigen::Matrix3d& R) {
  const Matrix6d B = blockJacobian(R);
  return B.transpose() * info * B;
}

Matrix6d informationFromMrpt(const Matrix6d& info_mrpt, const Eigen::Matrix3d& R) {
  const Eigen::Vector3d ypr = mrptYawPitchRoll(R);
  if (std::abs(std::cos(ypr(1))) < kMinCosPitch) {
    throw std::domain_error(
        "pitch " + std::to_string(ypr(1) * 180.0 / 3.14159265358979323846) +
        " deg is at gimbal lock: yaw/pitch/roll information cannot be converted");
  }
  Matrix6d B_inv = Matrix6d::Identity();
  B_inv.bottomRightCorner<3, 3>() = yawPitchRollToRotationVectorJacobian(ypr(1), ypr(2)).inverse();
  return B_inv.transpose() * info_mrpt * B_inv;
}

}  // namespace rgbdi::output
