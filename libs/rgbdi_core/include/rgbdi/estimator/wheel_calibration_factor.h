// The wheel factor with the wheel odometry's online calibration (doc/wheels.md "Online
// calibration"): WheelFactor's residual, with two more parameter blocks, a correction `yaw` [rad]
// about the wheel frame's z to the configured extrinsic (R_body_wheel = R_configured Rz(yaw)) and
// the wheel time offset td [s] (t_imu = t_wheel + td).
//
// Parameter blocks: pose_a (7), pose_b (7), s_v (1), s_w (1), yaw (1), td (1). The interval was
// cut at the offset cutTimeOffset() of its pre-integration; the motion follows td - that to
// first order (WheelPreintegration::calibratedMotion). With R_bw = R_configured Rz(yaw):
//   r_p     = R_bw^T (R_wa^T (p_wb + R_wb p_bw - p_wa) - p_bw) - dp(s, yaw, td)
//   r_theta = Log(Rz(dyaw(s, td))^T R_bw^T R_wa^T R_wb R_bw)
// so d r_p / d yaw = -e_z x (r_p + dp) - d dp / d yaw and d r_theta / d yaw = -e_z x r_theta
// (R_bw^T M R_bw = Rz(-yaw) (R_configured^T M R_configured) Rz(yaw), and Rz commutes with the
// wheels' Rz(dyaw)). Pose Jacobians as WheelFactor's (tangent perturbations, zero 7th column).
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Geometry>

#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {

class WheelCalibrationFactor : public ceres::SizedCostFunction<6, 7, 7, 1, 1, 1, 1> {
 public:
  /// `preintegration` is copied; `T_body_wheel` is the configured wheel frame in the body frame.
  WheelCalibrationFactor(const WheelPreintegration& preintegration,
                         const Eigen::Isometry3d& T_body_wheel);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The unweighted residual [r_p, r_theta] at the given states (for gates and statistics).
  Eigen::Matrix<double, 6, 1> error(const double* pose_a, const double* pose_b, double s_v,
                                    double s_w, double yaw, double td) const;

 private:
  bool evaluate(double const* const* parameters, double* residuals, double** jacobians,
                bool weighted) const;

  WheelPreintegration preint_;
  Eigen::Matrix3d R_bw0_;  ///< the configured R_body_wheel
  Eigen::Vector3d p_bw_;   ///< p_body_wheel [m]
};

}  // namespace rgbdi::estimator
