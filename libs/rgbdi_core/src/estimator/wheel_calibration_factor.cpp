#include "rgbdi/estimator/wheel_calibration_factor.h"

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {
namespace {

using PoseJacobian = Eigen::Matrix<double, 6, 7, Eigen::RowMajor>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

}  // namespace

WheelCalibrationFactor::WheelCalibrationFactor(const WheelPreintegration& preintegration,
                                               const Eigen::Isometry3d& T_body_wheel)
    : preint_(preintegration), R_bw0_(T_body_wheel.rotation()), p_bw_(T_body_wheel.translation()) {}

Vector6d WheelCalibrationFactor::error(const double* pose_a, const double* pose_b, double s_v,
                                       double s_w, double yaw, double td) const {
  const double* params[] = {pose_a, pose_b, &s_v, &s_w, &yaw, &td};
  Vector6d r;
  evaluate(params, r.data(), nullptr, false);
  return r;
}

bool WheelCalibrationFactor::Evaluate(double const* const* parameters, double* residuals,
                                      double** jacobians) const {
  return evaluate(parameters, residuals, jacobians, true);
}

bool WheelCalibrationFactor::evaluate(double const* const* parameters, double* residuals,
                                      double** jacobians, bool weighted) const {
  const Eigen::Map<const Eigen::Vector3d> pa(parameters[0]);
  const Eigen::Matrix3d Ra =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0] + 3).normalized().toRotationMatrix();
  const Eigen::Map<const Eigen::Vector3d> pb(parameters[1]);
  const Eigen::Matrix3d Rb =
      Eigen::Map<const Eigen::Quaterniond>(parameters[1] + 3).normalized().toRotationMatrix();
  const double s_v = parameters[2][0], s_w = parameters[3][0];
  const double yaw = parameters[4][0], td = parameters[5][0];
  const CalibratedWheelMotion m =
      preint_.calibratedMotion(s_v, s_w, yaw, td - preint_.cutTimeOffset());
  const Eigen::Matrix3d R_bw = R_bw0_ * rotZ(yaw);

  // y = R_a^T (p_b + R_b p_bw - p_a): the wheel origin at b in body frame a.
  const Eigen::Vector3d y = Ra.transpose() * (pb + Rb * p_bw_ - pa);
  const Eigen::Vector3d r_p = R_bw.transpose() * (y - p_bw_) - m.dp;
  const Eigen::Matrix3d E =
      rotZ(m.dyaw).transpose() * R_bw.transpose() * Ra.transpose() * Rb * R_bw;
  const Eigen::Vector3d r_theta = logSO3(E);
  const Vector6d w = weighted ? preint_.sqrtInformation() : Vector6d::Ones();
  Eigen::Map<Vector6d> out(residuals);
  out.head<3>() = r_p;
  out.tail<3>() = r_theta;
  out = w.asDiagonal() * out;
  if (jacobians == nullptr) return true;

  const Eigen::Matrix3d Jr_inv = rightJacobianInvSO3(r_theta);
  const Eigen::Matrix3d RbwT_RaT = R_bw.transpose() * Ra.transpose();
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d dtheta_ddyaw = -Jr_inv * E.transpose() * ez;
  if (jacobians[0]) {
    Eigen::Map<PoseJacobian> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = -RbwT_RaT;
    J.block<3, 3>(0, 3) = R_bw.transpose() * skew(y);
    J.block<3, 3>(3, 3) = -Jr_inv * R_bw.transpose() * Rb.transpose() * Ra;
    J = w.asDiagonal() * J;
  }
  if (jacobians[1]) {
    Eigen::Map<PoseJacobian> J(jacobians[1]);
    J.setZero();
    J.block<3, 3>(0, 0) = RbwT_RaT;
    J.block<3, 3>(0, 3) = -RbwT_RaT * Rb * skew(p_bw_);
    J.block<3, 3>(3, 3) = Jr_inv * R_bw.transpose();
    J = w.asDiagonal() * J;
  }
  const auto scalar = [&](int i, const Eigen::Vector3d& jp, const Eigen::Vector3d& jt) {
    if (!jacobians[i]) return;
    Eigen::Map<Vector6d> J(jacobians[i]);
    J.head<3>() = jp;
    J.tail<3>() = jt;
    J = w.asDiagonal() * J;
  };
  scalar(2, -m.ddp_dsv, Eigen::Vector3d::Zero());
  scalar(3, -m.ddp_dsw, dtheta_ddyaw * m.ddyaw_dsw);
  scalar(4, -ez.cross(r_p + m.dp) - m.ddp_dyaw, -ez.cross(r_theta));
  scalar(5, -m.ddp_dtd, dtheta_ddyaw * m.ddyaw_dtd);
  return true;
}

}  // namespace rgbdi::estimator
