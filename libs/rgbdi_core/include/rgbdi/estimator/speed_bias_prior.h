// Gaussian prior on a speed-bias block [v, ba, bg] with diagonal standard deviations. Used for the
// first window state: it encodes what the initialisation knows (zero velocity at a static start,
// the gyro bias from the static mean, accelerometer bias near zero) and flows into the
// marginalisation prior when that state leaves the window.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

namespace rgbdi::estimator {

class SpeedBiasPrior final : public ceres::SizedCostFunction<9, 9> {
 public:
  SpeedBiasPrior(const Eigen::Matrix<double, 9, 1>& mean, const Eigen::Matrix<double, 9, 1>& sigma)
      : mean_(mean), inv_sigma_(sigma.cwiseInverse()) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Map<const Eigen::Matrix<double, 9, 1>> x(parameters[0]);
    Eigen::Map<Eigen::Matrix<double, 9, 1>> r(residuals);
    r = inv_sigma_.cwiseProduct(x - mean_);
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>> J(jacobians[0]);
      J = inv_sigma_.asDiagonal();
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 9, 1> mean_;
  Eigen::Matrix<double, 9, 1> inv_sigma_;
};

}  // namespace rgbdi::estimator
