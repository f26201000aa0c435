#include "rgbdi/estimator/reprojection_factor.h"

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {

void ShiftedReprojection::reset(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
                                const Eigen::Isometry3d& T_body_cam, double sqrt_info) {
  obs_i_ = obs_i;
  obs_j_ = obs_j;
  R_bc_ = T_body_cam.rotation();
  t_bc_ = T_body_cam.translation();
  sqrt_info_ = sqrt_info;
}

void ShiftedReprojection::evaluate(double const* const* parameters, double dt_i, double dt_j,
                                   double* residuals, double** jacobians, int shifts,
                                   const double* shift_i, const double* shift_j) const {
  const Eigen::Vector3d Pi(parameters[0][0], parameters[0][1], parameters[0][2]);
  const Eigen::Quaterniond Qi(parameters[0][6], parameters[0][3], parameters[0][4],
                              parameters[0][5]);
  const Eigen::Vector3d Pj(parameters[1][0], parameters[1][1], parameters[1][2]);
  const Eigen::Quaterniond Qj(parameters[1][6], parameters[1][3], parameters[1][4],
                              parameters[1][5]);
  const double inv_dep = parameters[2][0];

  const Eigen::Matrix3d Ri = Qi.toRotationMatrix();
  const Eigen::Matrix3d Rj = Qj.toRotationMatrix();

  Eigen::Vector3d pts_i = obs_i_.xn;
  pts_i.head<2>() -= dt_i * obs_i_.velocity;
  Eigen::Vector3d pts_j = obs_j_.xn;
  pts_j.head<2>() -= dt_j * obs_j_.velocity;

  const Eigen::Vector3d p_ci = pts_i / inv_dep;
  const Eigen::Vector3d p_bi = R_bc_ * p_ci + t_bc_;
  const Eigen::Vector3d p_w = Ri * p_bi + Pi;
  const Eigen::Vector3d p_bj = Rj.transpose() * (p_w - Pj);
  const Eigen::Vector3d p_cj = R_bc_.transpose() * (p_bj - t_bc_);
  const double z = p_cj.z();

  Eigen::Map<Eigen::Vector2d> r(residuals);
  r = sqrt_info_ * (p_cj.head<2>() / z - pts_j.head<2>());

  if (!jacobians) return;

  Eigen::Matrix<double, 2, 3> reduce;
  reduce << 1.0 / z, 0.0, -p_cj.x() / (z * z), 0.0, 1.0 / z, -p_cj.y() / (z * z);
  reduce *= sqrt_info_;
  const Eigen::Matrix3d R_cb = R_bc_.transpose();

  if (jacobians[0]) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> J(jacobians[0]);
    Eigen::Matrix<double, 3, 6> d;
    d.leftCols<3>() = Rj.transpose();
    d.rightCols<3>() = -Rj.transpose() * Ri * skew(p_bi);
    J.leftCols<6>() = reduce * R_cb * d;
    J.col(6).setZero();
  }
  if (jacobians[1]) {
    Eigen::Map<Eigen::Matrix<double, 2, 7, Eigen::RowMajor>> J(jacobians[1]);
    Eigen::Matrix<double, 3, 6> d;
    d.leftCols<3>() = -Rj.transpose();
    d.rightCols<3>() = skew(p_bj);
    J.leftCols<6>() = reduce * R_cb * d;
    J.col(6).setZero();
  }
  const Eigen::Matrix3d R_cj_ci = R_cb * Rj.transpose() * Ri * R_bc_;
  if (jacobians[2]) {
    Eigen::Map<Eigen::Vector2d> J(jacobians[2]);
    J = reduce * R_cj_ci * pts_i * (-1.0 / (inv_dep * inv_dep));
  }
  // d pts_i / d(shift s) = -shift_i[s] v_i, d pts_j / d(shift s) = -shift_j[s] v_j.
  for (int s = 0; s < shifts; ++s) {
    if (!jacobians[3 + s]) continue;
    Eigen::Map<Eigen::Vector2d> J(jacobians[3 + s]);
    Eigen::Vector3d dpi;
    dpi << -shift_i[s] * obs_i_.velocity, 0.0;
    J = reduce * R_cj_ci * dpi / inv_dep + sqrt_info_ * shift_j[s] * obs_j_.velocity;
  }
}

ReprojectionFactor::ReprojectionFactor(const FeatureMeasurement& obs_i,
                                       const FeatureMeasurement& obs_j,
                                       const Eigen::Isometry3d& T_body_cam, double sqrt_info) {
  reset(obs_i, obs_j, T_body_cam, sqrt_info);
}

void ReprojectionFactor::reset(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
                               const Eigen::Isometry3d& T_body_cam, double sqrt_info) {
  core_.reset(obs_i, obs_j, T_body_cam, sqrt_info);
}

bool ReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                  double** jacobians) const {
  const double td = parameters[3][0];
  static constexpr double kUnit[1] = {1.0};
  core_.evaluate(parameters, td - core_.obsI().td_at_stamp, td - core_.obsJ().td_at_stamp,
                 residuals, jacobians, 1, kUnit, kUnit);
  return true;
}

}  // namespace rgbdi::estimator
