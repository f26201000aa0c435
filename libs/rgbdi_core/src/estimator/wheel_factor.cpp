#include "rgbdi/estimator/wheel_factor.h"

#include "estimator/wheel_relative_pose.h"

namespace rgbdi::estimator {
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
  const double s_v = parameters[2][0], s_w = parameters[3][0];
  Eigen::Vector3d dp, ddp_dsw;
  double dyaw = 0.0;
  preint_.motion(s_v, s_w, &dp, &dyaw, &ddp_dsw);
  const WheelResidual w = weighted ? preint_.sqrtInformation() : WheelResidual::Ones();
  const WheelRelativePose r =
      wheelRelativePose(parameters, R_bw_, p_bw_, dp, dyaw, w, residuals, jacobians);
  if (jacobians == nullptr) return true;
  if (jacobians[2]) {
    Eigen::Map<WheelResidual> J(jacobians[2]);
    J.setZero();
    Eigen::Vector3d unscaled;
    preint_.motion(1.0, s_w, &unscaled, nullptr);
    J.head<3>() = -unscaled;
    J = w.asDiagonal() * J;
  }
  if (jacobians[3]) {
    Eigen::Map<WheelResidual> J(jacobians[3]);
    J.setZero();
    J.head<3>() = -ddp_dsw;
    J.tail<3>() = -r.Jr_inv * r.E.transpose() * Eigen::Vector3d::UnitZ() * preint_.reportedYaw();
    J = w.asDiagonal() * J;
  }
  return true;
}

}  // namespace rgbdi::estimator
