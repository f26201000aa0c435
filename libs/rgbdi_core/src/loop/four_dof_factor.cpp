#include "rgbdi/loop/four_dof_factor.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rgbdi::loop {

FourDofEdgeFactor::FourDofEdgeFactor(const FourDofDelta& measured, double sigma_pos_m,
                                     double sigma_yaw_rad)
    : measured_(measured) {
  if (!(std::isfinite(sigma_pos_m) && sigma_pos_m > 0.0) ||
      !(std::isfinite(sigma_yaw_rad) && sigma_yaw_rad > 0.0))
    throw std::invalid_argument("FourDofEdgeFactor: sigmas must be positive, got position " +
                                std::to_string(sigma_pos_m) + " m, yaw " +
                                std::to_string(sigma_yaw_rad) + " rad");
  w_pos_ = 1.0 / sigma_pos_m;
  w_yaw_ = 1.0 / sigma_yaw_rad;
}

Eigen::Vector4d FourDofEdgeFactor::residual(const double* x_i, const double* x_j) const {
  const double* params[2] = {x_i, x_j};
  Eigen::Vector4d r;
  Evaluate(params, r.data(), nullptr);
  return r;
}

bool FourDofEdgeFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> p_i(parameters[0]);
  const double yaw_i = parameters[0][3];
  const Eigen::Map<const Eigen::Vector3d> p_j(parameters[1]);
  const double yaw_j = parameters[1][3];

  const double c = std::cos(yaw_i), s = std::sin(yaw_i);
  Eigen::Matrix3d Rt;  // Rz(yaw_i)^T
  Rt << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  const Eigen::Vector3d d = p_j - p_i;

  Eigen::Map<Eigen::Vector4d> r(residuals);
  r.head<3>() = w_pos_ * (Rt * d - measured_.t_m);
  r[3] = w_yaw_ * wrapAngle(yaw_j - yaw_i - measured_.yaw_rad);

  if (jacobians == nullptr) return true;
  if (jacobians[0] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J.topLeftCorner<3, 3>() = -w_pos_ * Rt;
    // d(Rz(yaw_i)^T)/dyaw_i * d
    J(0, 3) = w_pos_ * (-s * d.x() + c * d.y());
    J(1, 3) = w_pos_ * (-c * d.x() - s * d.y());
    J(3, 3) = -w_yaw_;
  }
  if (jacobians[1] != nullptr) {
    Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> J(jacobians[1]);
    J.setZero();
    J.topLeftCorner<3, 3>() = w_pos_ * Rt;
    J(3, 3) = w_yaw_;
  }
  return true;
}

}  // namespace rgbdi::loop
