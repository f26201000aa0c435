#include "rgbdi/estimator/wheel_calibration_factor.h"

#include "estimator/wheel_relative_pose.h"

namespace rgbdi::estimator {
namespace {

using Vector6d = WheelResidual;

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
  const double s_v = parameters[2][0], s_w = parameters[3][0];
  const double yaw = parameters[4][0], td = parameters[5][0];
  const CalibratedWheelMotion m =
      preint_.calibratedMotion(s_v, s_w, yaw, td - preint_.cutTimeOffset());
  const Eigen::Matrix3d R_bw = R_bw0_ * rotZ(yaw);

  const Vector6d w = weighted ? preint_.sqrtInformation() : Vector6d::Ones();
  const WheelRelativePose r =
      wheelRelativePose(parameters, R_bw, p_bw_, m.dp, m.dyaw, w, residuals, jacobians);
  if (jacobians == nullptr) return true;

  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d dtheta_ddyaw = -r.Jr_inv * r.E.transpose() * ez;
  const auto scalar = [&](int i, const Eigen::Vector3d& jp, const Eigen::Vector3d& jt) {
    if (!jacobians[i]) return;
    Eigen::Map<Vector6d> J(jacobians[i]);
    J.head<3>() = jp;
    J.tail<3>() = jt;
    J = w.asDiagonal() * J;
  };
  scalar(2, -m.ddp_dsv, Eigen::Vector3d::Zero());
  scalar(3, -m.ddp_dsw, dtheta_ddyaw * m.ddyaw_dsw);
  scalar(4, -ez.cross(r.r_p + m.dp) - m.ddp_dyaw, -ez.cross(r.r_theta));
  scalar(5, -m.ddp_dtd, dtheta_ddyaw * m.ddyaw_dtd);
  return true;
}

}  // namespace rgbdi::estimator
