#include "rgbdi/estimator/wheel_factor.h"

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {
namespace {

using PoseJacobian = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;

Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

}  // namespace

WheelFactor::WheelFactor(const WheelPreintegration& preintegration,
                         const Eigen::Isometry3d& T_body_wheel)
    : preint_(preintegration), R_bw_(T_body_wheel.rotation()), p_bw_(T_body_wheel.translation()) {}

Eigen::Matrix<double, 6, 1> WheelFactor::error(const double* pose_a, const double* pose_b,
                                               double s_v, double s_w) const {
  const double* params[] = {pose_a, pose_b, &s_v, &s_w};
  Eigen::Matrix<double, 6, 1> r;
  evaluate(params, r.data(), nullptr, false);
  return r;
}

bool WheelFactor::Evaluate(double const* const* parameters, double* residuals,
                           double** jacobians) const {
  return evaluate(parameters, residuals, jacobians, true);
}

bool WheelFactor::evaluate(double const* const* parameters, double* residuals, double** jacobians,
                           bool weighted) const {
  const Eigen::Map<const Eigen::Vector3d> pa(parameters[0]);
  const Eigen::Matrix3d Ra =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0] + 3).normalized().toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> pb(parameters[1]);
  const Eigen::Matrix3d Rb =
      Eigen::Map<const Eigen::Quaterniond>(parameters[1] + 3).normalized().toRotationMatrix();
  const double s_v = parameters[2][0], s_w = parameters[3][0];

  Eigen::Vector3d dp, ddp_dsw;
  double dyaw = 0.0;
  preint_.motion(s_v, s_w, &dp, &dyaw, &ddp_dsw);

  // y = R_a^T (p_b + R_b p_bw - p_a): the wheel origin at b in body frame a.
  const Eigen::Vector3d y = Ra.transpose() * (pb + Rb * p_bw_ - pa);
  const Eigen::Vector3d r_p = R_bw_.transpose() * (y - p_bw_) - dp;
  const Eigen::Matrix3d E =
      rotZ(dyaw).transpose() * R_bw_.transpose() * Ra.transpose() * Rb * R_bw_;
  const Eigen::Vector3d r_theta = logSO3(E);
  const Eigen::Matrix<double, 6, 1> w =
      weighted ? preint_.sqrtInformation() : Eigen::Matrix<double, 6, 1>::Ones();
  Eigen::Map<Eigen::Matrix<double, 6, 1>> out(residuals);
  out.head<3>() = r_p;
  out.tail<3>() = r_theta;
  out = w.asDiagonal() * out;
  if (jacobians == nullptr) return true;

  const Eigen::Matrix3d Jr_inv = rightJacobianInvSO3(r_theta);
  const Eigen::Matrix3d RbwT_RaT = R_bw_.transpose() * Ra.transpose();
  if (jacobians[0]) {
    Eigen::Map<PoseJacobian> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = -RbwT_RaT;
    J.block<3, 3>(0, 3) = R_bw_.transpose() * skew(y);
    J.block<3, 3>(3, 3) = -Jr_inv * R_bw_.transpose() * Rb.transpose() * Ra;
    J = w.asDiagonal() * J;
  }
  if (jacobians[1]) {
    Eigen::Map<PoseJacobian> J(jacobians[1]);
    J.setZero();
    J.block<3, 3>(0, 0) = RbwT_RaT;
    J.block<3, 3>(0, 3) = -RbwT_RaT * Rb * skew(p_bw_);
    J.block<3, 3>(3, 3) = Jr_inv * R_bw_.transpose();
    J = w.asDiagonal() * J;
  }
  if (jacobians[2]) {
    Eigen::Map<Eigen::Matrix<double, 6, 1>> J(jacobians[2]);
    J.setZero();
    Eigen::Vector3d unscaled;
    preint_.motion(1.0, s_w, &unscaled, nullptr);
    J.head<3>() = -unscaled;
    J = w.asDiagonal() * J;
  }
  if (jacobians[3]) {
    Eigen::Map<Eigen::Matrix<double, 6, 1>> J(jacobians[3]);
    J.setZero();
    J.head<3>() = -ddp_dsw;
    J.tail<3>() = -Jr_inv * E.transpose() * Eigen::Vector3d::UnitZ() * preint_.reportedYaw();
    J = w.asDiagonal() * J;
  }
  return true;
}

}  // namespace rgbdi::estimator
