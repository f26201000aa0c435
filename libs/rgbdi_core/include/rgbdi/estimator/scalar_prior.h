// Gaussian prior on a scalar parameter block: a feature's inverse depth [1/m] from its verified
// sensor depth, or the camera-IMU time offset [s] from the configuration.
#pragma once

#include <ceres/sized_cost_function.h>

#include <cmath>

namespace rgbdi::estimator {

class ScalarPrior final : public ceres::SizedCostFunction<1, 1> {
 public:
  ScalarPrior(double mean, double sigma) : mean_(mean), inv_sigma_(1.0 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = inv_sigma_ * (parameters[0][0] - mean_);
    if (jacobians && jacobians[0]) jacobians[0][0] = inv_sigma_;
    return true;
  }

 private:
  double mean_;
  double inv_sigma_;
};

}  // namespace rgbdi::estimator
