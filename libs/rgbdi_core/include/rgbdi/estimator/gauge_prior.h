// Fixes the 4 unobservable directions of visual-inertial odometry (position and yaw) on one pose
// block by a stiff prior, leaving roll and pitch free (gravity makes them observable).
// Without it the window drifts freely along the gauge directions between updates.
// Jacobian columns follow PoseManifold: [dp, dtheta] (right perturbation), 7th column zero.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rgbdi::estimator {

class GaugePrior final : public ceres::SizedCostFunction<4, 7> {
 public:
  /// `pose` = [p, q] to hold; `stiffness` is the sqrt information [1/m, 1/rad].
  GaugePrior(const double* pose, double stiffness);
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  Eigen::Vector3d p0_;
  double yaw0_;
  double w_;
};

}  // namespace rgbdi::estimator
