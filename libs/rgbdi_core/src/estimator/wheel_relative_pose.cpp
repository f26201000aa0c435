#include "estimator/wheel_relative_pose.h"

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {

WheelRelativePose wheelRelativePose(double const* const* parameters, const Eigen::Matrix3d& R_bw,
                                    const Eigen::Vector3d& p_bw, const Eigen::Vector3d& dp,
                                    double dyaw, const WheelResidual& w, double* residuals,
                                    double** jacobians) {
  using PoseJacobian = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;
  const Eigen::Map<const Eigen::Vector3d> pa(parameters[0]);
  const Eigen::Matrix3d Ra =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0] + 3).normalized().toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> pb(parameters[1]);
  const Eigen::Matrix3d Rb =
      Eigen::Map<const Eigen::Quaterniond>(parameters[1] + 3).normalized().toRotationMatrix();

  WheelRelativePose r;
  // y = R_a^T (p_b + R_b p_bw - p_a): the wheel origin at b in body frame a.
  const Eigen::Vector3d y = Ra.transpose() * (pb + Rb * p_bw - pa);
  r.r_p = R_bw.transpose() * (y - p_bw) - dp;
  const Eigen::Matrix3d Rz_dyaw = Eigen::AngleAxisd(dyaw, Eigen::Vector3d::UnitZ()).matrix();
  r.E = Rz_dyaw.transpose() * R_bw.transpose() * Ra.transpose() * Rb * R_bw;
  r.r_theta = logSO3(r.E);
  Eigen::Map<WheelResidual> out(residuals);
  out.head<3>() = r.r_p;
  out.tail<3>() = r.r_theta;
  out = w.asDiagonal() * out;
  if (jacobians == nullptr) return r;

  r.Jr_inv = rightJacobianInvSO3(r.r_theta);
  const Eigen::Matrix3d RbwT_RaT = R_bw.transpose() * Ra.transpose();
  if (jacobians[0]) {
    Eigen::Map<PoseJacobian> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = -RbwT_RaT;
    J.block<3, 3>(0, 3) = R_bw.transpose() * skew(y);
    J.block<3, 3>(3, 3) = -r.Jr_inv * R_bw.transpose() * Rb.transpose() * Ra;
    J = w.asDiagonal() * J;
  }
  if (jacobians[1]) {
    Eigen::Map<PoseJacobian> J(jacobians[1]);
    J.setZero();
    J.block<3, 3>(0, 0) = RbwT_RaT;
    J.block<3, 3>(0, 3) = -RbwT_RaT * Rb * skew(p_bw);
    J.block<3, 3>(3, 3) = r.Jr_inv * R_bw.transpose();
    J = w.asDiagonal() * J;
  }
  return r;
}

}  // namespace rgbdi::estimator
