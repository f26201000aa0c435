#include "rgbdi/estimator/wheel_options.h"

#include <cmath>
#include <sstream>

namespace rgbdi::estimator {

WheelOptions WheelOptions::load(IniReader& ini) {
  WheelOptions o;
  const std::string s = "wheel";
  o.enable = ini.getBool(s, "enable", o.enable);
  o.time_offset_s = ini.getDouble(s, "time_offset_s", o.time_offset_s, -0.5, 0.5);
  Eigen::VectorXd r = ini.getVector(s, "R_body_wheel",
                                    (Eigen::VectorXd(9) << 1, 0, 0, 0, 1, 0, 0, 0, 1).finished());
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = r[3 * i + j];
  const double orth_err = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (orth_err > 1e-3 || R.determinant() < 0.0) {
    std::ostringstream os;
    os << "not a rotation matrix (|R^T R - I| = " << orth_err << ", det = " << R.determinant()
       << "); give 9 numbers row-major with |R^T R - I| <= 1e-3 and det = +1";
    ini.fail(s, "R_body_wheel", os.str());
  }
  o.T_body_wheel.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  const Eigen::VectorXd t = ini.getVector(s, "t_body_wheel_m", Eigen::VectorXd::Zero(3));
  if (t.norm() > 5.0)
    ini.fail(s, "t_body_wheel_m", "translation longer than 5 m; accepted range |t| <= 5 m");
  o.T_body_wheel.translation() = t;
  WheelNoise& n = o.noise;
  n.forward_sigma_per_sqrt_m =
      ini.getDouble(s, "forward_sigma_per_sqrt_m", n.forward_sigma_per_sqrt_m, 1e-6, 10.0);
  n.lateral_sigma_per_sqrt_m =
      ini.getDouble(s, "lateral_sigma_per_sqrt_m", n.lateral_sigma_per_sqrt_m, 1e-6, 10.0);
  n.vertical_sigma_per_sqrt_m =
      ini.getDouble(s, "vertical_sigma_per_sqrt_m", n.vertical_sigma_per_sqrt_m, 1e-6, 10.0);
  n.yaw_sigma_per_sqrt_rad =
      ini.getDouble(s, "yaw_sigma_per_sqrt_rad", n.yaw_sigma_per_sqrt_rad, 1e-6, 10.0);
  n.yaw_sigma_per_sqrt_m =
      ini.getDouble(s, "yaw_sigma_per_sqrt_m", n.yaw_sigma_per_sqrt_m, 1e-6, 10.0);
  n.tilt_sigma_per_sqrt_m =
      ini.getDouble(s, "tilt_sigma_per_sqrt_m", n.tilt_sigma_per_sqrt_m, 1e-6, 10.0);
  n.min_sigma_m = ini.getDouble(s, "min_sigma_m", n.min_sigma_m, 1e-6, 10.0);
  n.min_sigma_rad = ini.getDouble(s, "min_sigma_rad", n.min_sigma_rad, 1e-6, 10.0);
  o.estimate_scale = ini.getBool(s, "estimate_scale", o.estimate_scale);
  o.scale_prior_sigma = ini.getDouble(s, "scale_prior_sigma", o.scale_prior_sigma, 1e-6, 10.0);
  o.estimate_extrinsic_yaw = ini.getBool(s, "estimate_extrinsic_yaw", o.estimate_extrinsic_yaw);
  o.extrinsic_yaw_prior_sigma_rad = ini.getDouble(s, "extrinsic_yaw_prior_sigma_rad",
                                                  o.extrinsic_yaw_prior_sigma_rad, 1e-6, 10.0);
  o.extrinsic_yaw_max_rad =
      ini.getDouble(s, "extrinsic_yaw_max_rad", o.extrinsic_yaw_max_rad, 0.0, M_PI);
  o.estimate_time_offset = ini.getBool(s, "estimate_time_offset", o.estimate_time_offset);
  o.time_offset_prior_sigma_s =
      ini.getDouble(s, "time_offset_prior_sigma_s", o.time_offset_prior_sigma_s, 1e-6, 10.0);
  o.time_offset_max_change_s =
      ini.getDouble(s, "time_offset_max_change_s", o.time_offset_max_change_s, 0.0, 1.0);
  o.gate_chi2 = ini.getDouble(s, "gate_chi2", o.gate_chi2, 0.0, 1e9);
  o.max_blind_s = ini.getDouble(s, "max_blind_s", o.max_blind_s, 0.0, 3600.0);
  o.reading_lag_s = ini.getDouble(s, "reading_lag_s", o.reading_lag_s, 0.0, 10.0);
  o.fault_motion_ratio = ini.getDouble(s, "fault_motion_ratio", o.fault_motion_ratio, 0.0, 1.0);
  o.direction_from_gyro =
      ini.getEnum(s, "direction_from_gyro", o.direction_from_gyro, {"never", "blind", "always"});
  o.ground_plane_sigma_m =
      ini.getDouble(s, "ground_plane_sigma_m", o.ground_plane_sigma_m, 0.0, 10.0);
  o.ground_plane_tilt_sigma_rad =
      ini.getDouble(s, "ground_plane_tilt_sigma_rad", o.ground_plane_tilt_sigma_rad, 1e-6, 10.0);
  o.ground_plane_gate_chi2 =
      ini.getDouble(s, "ground_plane_gate_chi2", o.ground_plane_gate_chi2, 0.0, 1e9);
  o.start_from_wheels = ini.getBool(s, "start_from_wheels", o.start_from_wheels);
  o.start_window_s = ini.getDouble(s, "start_window_s", o.start_window_s, 0.01, 10.0);
  o.start_max_gravity_dev_m_s2 =
      ini.getDouble(s, "start_max_gravity_dev_m_s2", o.start_max_gravity_dev_m_s2, 0.0, 100.0);
  o.start_max_rate_dev_rad_s =
      ini.getDouble(s, "start_max_rate_dev_rad_s", o.start_max_rate_dev_rad_s, 0.0, 100.0);
  o.start_velocity_sigma_m_s =
      ini.getDouble(s, "start_velocity_sigma_m_s", o.start_velocity_sigma_m_s, 1e-6, 100.0);
  return o;
}

}  // namespace rgbdi::estimator
