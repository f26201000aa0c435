// Gaussian prior on a feature's inverse depth [1/m] from the verified sensor depth.
#pragma once

#include <ceres/sized_cost_function.h>

namespace rgbdi::estimator {

class InverseDepthPrior final : public ceres::SizedCostFunction<1, 1> {
 public:
  InverseDepthPrior(double inv_depth, double sigma) : mean_(inv_depth), inv_sigma_(1.0 / sigma) {}
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
