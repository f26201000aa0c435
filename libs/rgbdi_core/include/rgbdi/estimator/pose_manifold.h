// Manifold of a pose parameter block [px py pz qx qy qz qw] (T_world_body, Eigen quaternion order).
// Tangent [dp, dtheta]: p <- p + dp, q <- q * Exp(dtheta) (right perturbation).
//
// PlusJacobian is [I6; 0]: every analytic cost function in rgbdi writes its 7 pose Jacobian columns
// as the derivative w.r.t. [dp, dtheta] in the first six and zero in the seventh, so Ceres' chain
// rule (J_ambient * PlusJacobian) yields exactly the tangent Jacobian without quaternion algebra.
#pragma once

#include <ceres/manifold.h>

namespace rgbdi::estimator {

class PoseManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace rgbdi::estimator
