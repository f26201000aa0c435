// Ceres cost function of one pre-integrated wheel-odometry interval between window frames a and
// b.
//
// Parameter blocks: pose_a (7), pose_b (7), s_v (1), s_w (1) (forward-speed and yaw-rate scale
// factors of the odometry). With T_world_wheel = T_world_body * T_body_wheel at a and b, the
// residual (6) is sqrt_info .* [r_p, r_theta]:
//   r_p     = R_wa^T (p_wb - p_wa) - dp(s)   (dp's z = 0 unless pre-integrated in 3-D)
//   r_theta = Log(Rz(dyaw(s))^T R_wa^T R_wb)
// (WheelPreintegration gives dp, dyaw). The z of r_p and the x, y of r_theta hold the wheel frame
// on its ground plane between the two frames (the robot neither leaves the ground nor rolls over
// it), with the loose sigmas of the noise model; in 3-D the rotation rows have no weight.
// Jacobians w.r.t. a pose block have 7 columns: the derivative w.r.t. the tangent perturbation
// [dp, dtheta] (p <- p + dp, q <- q * Exp(dtheta)) and a zero 7th column, as ImuFactor's.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Geometry>

#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {

class WheelFactor : public ceres::SizedCostFunction<6, 7, 7, 1, 1> {
 public:
  /// `preintegration` is copied; `T_body_wheel` is the wheel frame in the body frame.
  WheelFactor(const WheelPreintegration& preintegration, const Eigen::Isometry3d& T_body_wheel);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The unweighted residual [r_p, r_theta] at the given states (for gates and statistics).
  Eigen::Matrix<double, 6, 1> error(const double* pose_a, const double* pose_b, double s_v,
                                    double s_w) const;
  const WheelPreintegration& preintegration() const { return preint_; }

 private:
  bool evaluate(double const* const* parameters, double* residuals, double** jacobians,
                bool weighted) const;

  WheelPreintegration preint_;
  Eigen::Matrix3d R_bw_;  ///< R_body_wheel
  Eigen::Vector3d p_bw_;  ///< p_body_wheel [m]
};

}  // namespace rgbdi::estimator
