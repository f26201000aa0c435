#include "rgbdi/estimator/gauge_prior.h"

#include <cmath>

namespace rgbdi::estimator {
namespace {
double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }
}  // namespace

GaugePrior::GaugePrior(const double* pose, double stiffness)
    : p0_(pose[0], pose[1], pose[2]), w_(stiffness) {
  const Eigen::Matrix3d R =
      Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]).toRotationMatrix();
  yaw0_ = std::atan2(R(1, 0), R(0, 0));
}

bool GaugePrior::Evaluate(double const* const* parameters, double* residuals,
                          double** jacobians) const {
  const double* x = parameters[0];
  const Eigen::Matrix3d R = Eigen::Quaterniond(x[6], x[3], x[4], x[5]).toRotationMatrix();
  for (int i = 0; i < 3; ++i) residuals[i] = w_ * (x[i] - p0_[i]);
  residuals[3] = w_ * wrapAngle(std::atan2(R(1, 0), R(0, 0)) - yaw0_);
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 4, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.block<3, 3>(0, 0) = w_ * Eigen::Matrix3d::Identity();
    // yaw = atan2(R10, R00); with R <- R Exp(theta): dR_i0 = R_i1 theta_z - R_i2 theta_y.
    const double den = R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0);
    J(3, 4) = w_ * (R(1, 0) * R(0, 2) - R(0, 0) * R(1, 2)) / den;
    J(3, 5) = w_ * (R(0, 0) * R(1, 1) - R(1, 0) * R(0, 1)) / den;
  }
  return true;
}

}  // namespace rgbdi::estimator
