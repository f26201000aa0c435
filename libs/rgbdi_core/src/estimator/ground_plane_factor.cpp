#include "rgbdi/estimator/ground_plane_factor.h"

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {

GroundPlaneFactor::GroundPlaneFactor(double z0, double sigma_z, double sigma_tilt,
                                     const Eigen::Isometry3d& T_body_wheel)
    : z0_(z0),
      sqrt_info_(1.0 / sigma_z, 1.0 / sigma_tilt, 1.0 / sigma_tilt),
      R_bw_(T_body_wheel.rotation()),
      p_bw_(T_body_wheel.translation()) {}

double GroundPlaneFactor::squaredNormalised(const double* pose) const {
  const double* params[] = {pose};
  Eigen::Vector3d r;
  Evaluate(params, r.data(), nullptr);
  return r.squaredNorm();
}

bool GroundPlaneFactor::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> p(parameters[0]);
  const Eigen::Matrix3d R =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0] + 3).normalized().toRotationMatrix();
  const Eigen::Vector3d u = R_bw_ * Eigen::Vector3d::UnitZ();  // the wheel's up axis in the body
  const Eigen::Vector3d n = R * u;
  Eigen::Map<Eigen::Vector3d> out(residuals);
  out << (p + R * p_bw_).z() - z0_, n.x(), n.y();
  out = sqrt_info_.asDiagonal() * out;
  if (jacobians && jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 3, 7, Eigen::RowMajor>> J(jacobians[0]);
    J.setZero();
    J(0, 2) = 1.0;
    // R (I + [dtheta]x) v = R v - R [v]x dtheta.
    J.block<1, 3>(0, 3) = -(R * skew(p_bw_)).row(2);
    J.block<2, 3>(1, 3) = -(R * skew(u)).topRows<2>();
    J = sqrt_info_.asDiagonal() * J;
  }
  return true;
}

}  // namespace rgbdi::estimator
