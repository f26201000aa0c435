#include "rgbdi/estimator/pose_manifold.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {

bool PoseManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  Eigen::Map<const Eigen::Vector3d> p(x);
  Eigen::Map<const Eigen::Quaterniond> q(x + 3);
  Eigen::Map<const Eigen::Vector3d> dp(delta);
  Eigen::Map<const Eigen::Vector3d> dth(delta + 3);
  Eigen::Map<Eigen::Vector3d> p_out(x_plus_delta);
  Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
  p_out = p + dp;
  q_out = (q * expQuat(dth)).normalized();
  return true;
}

bool PoseManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.topRows<6>().setIdentity();
  return true;
}

bool PoseManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  Eigen::Map<const Eigen::Vector3d> py(y), px(x);
  Eigen::Map<const Eigen::Quaterniond> qy(y + 3), qx(x + 3);
  Eigen::Map<Eigen::Matrix<double, 6, 1>> d(y_minus_x);
  d.head<3>() = py - px;
  d.tail<3>() = logSO3((qx.conjugate() * qy).normalized().toRotationMatrix());
  return true;
}

bool PoseManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
  J.setZero();
  J.leftCols<6>().setIdentity();
  return true;
}

}  // namespace rgbdi::estimator
