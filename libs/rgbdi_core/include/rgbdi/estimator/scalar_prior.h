// Gaussian prior on a scalar parameter block: a feature's inverse depth [1/m] from its verified
// sensor depth, or the camera-IMU time offset [s] from the configuration.
// SplitScalarPrior is the same cost written as two equal halves (r/sqrt2, r/sqrt2): every residual
// on an inverse depth then has two rows like the reprojection residuals, which lets Ceres use its
// Schur eliminator specialised on two-row blocks.
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

class SplitScalarPrior final : public ceres::SizedCostFunction<2, 1> {
 public:
  SplitScalarPrior(double mean, double sigma) : mean_(mean), half_inv_sigma_(M_SQRT1_2 / sigma) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    residuals[0] = residuals[1] = half_inv_sigma_ * (parameters[0][0] - mean_);
    if (jacobians && jacobians[0]) jacobians[0][0] = jacobians[0][1] = half_inv_sigma_;
    return true;
  }

 private:
  double mean_;
  double half_inv_sigma_;  ///< 1 / (sqrt(2) sigma)
};

}  // namespace rgbdi::estimator
