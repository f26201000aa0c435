// Ceres cost function of the soft ground-plane constraint of a flat-floor robot (doc/wheels.md
// "Ground plane"): the wheel frame of one window frame lies on the horizontal plane z = z0 of the
// (gravity-aligned) world, upright.
//
// Parameter block: pose (7, T_world_body). With the wheel origin p_w = p + R p_body_wheel and the
// wheel frame's up axis n = R R_body_wheel e_z, the residual (3) is
//   sqrt_info .* [p_w.z - z0, n.x, n.y]
// (n.x, n.y: the tilt, about sin of roll and pitch). Jacobian: 7 columns, the derivative w.r.t.
// the tangent perturbation [dp, dtheta] (p <- p + dp, q <- q * Exp(dtheta)) and a zero 7th.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Geometry>

namespace rgbdi::estimator {

class GroundPlaneFactor : public ceres::SizedCostFunction<3, 7> {
 public:
  /// z0 [m]: the plane's height; sigma_z [m], sigma_tilt [rad].
  GroundPlaneFactor(double z0, double sigma_z, double sigma_tilt,
                    const Eigen::Isometry3d& T_body_wheel);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The squared normalised residual at `pose` (the gate's Mahalanobis distance).
  double squaredNormalised(const double* pose) const;

 private:
  double z0_;
  Eigen::Vector3d sqrt_info_;
  Eigen::Matrix3d R_bw_;
  Eigen::Vector3d p_bw_;
};

}  // namespace rgbdi::estimator
