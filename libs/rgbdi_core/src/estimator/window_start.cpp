#include "estimator/window_start.h"

#include "estimator/window_state.h"
#include "rgbdi/estimator/initializer.h"

namespace rgbdi::estimator {

void adoptRestingStart(WindowState& state, const Stillness& still, const Eigen::Vector3d& p0,
                       double yaw0, const EstimatorOptions& opt) {
  const Eigen::Matrix3d R = attitudeFromGravity(still.mean_acc, yaw0);
  WindowSlot& s = state.frames.front();
  s.setPose(p0, Eigen::Quaterniond(R));
  s.setV(Eigen::Vector3d::Zero());
  s.setBiases(Eigen::Vector3d::Zero(), still.mean_gyr);
  StartPrior& prior = state.start_prior;
  prior.mean.setZero();
  prior.mean.tail<3>() = still.mean_gyr;
  prior.sigma << Eigen::Vector3d::Constant(opt.init_static_velocity_sigma_m_s),
      Eigen::Vector3d::Constant(opt.init_acc_bias_sigma_m_s2),
      Eigen::Vector3d::Constant(opt.init_gyr_bias_sigma_rad_s);
  prior.active = true;
}

void adoptWheelStart(WindowState& state, const WheelStart& start, const Eigen::Vector3d& p0,
                     double yaw0, const EstimatorOptions& opt) {
  const Eigen::Matrix3d R = attitudeFromGravity(start.up_body, yaw0);
  WindowSlot& s = state.frames.front();
  s.setPose(p0, Eigen::Quaterniond(R));
  s.setV(R * start.v_body);
  s.setBiases(Eigen::Vector3d::Zero(), start.bg);
  StartPrior& prior = state.start_prior;
  prior.mean.setZero();
  prior.mean.head<3>() = s.v();
  prior.mean.tail<3>() = start.bg;
  prior.sigma << Eigen::Vector3d::Constant(opt.wheel.start_velocity_sigma_m_s),
      Eigen::Vector3d::Constant(opt.init_acc_bias_sigma_m_s2),
      Eigen::Vector3d::Constant(opt.init_gyr_bias_sigma_rad_s);
  prior.active = true;
}

void adoptMovingStart(WindowState& state, const MovingStart& start, const Eigen::Vector3d& p0,
                      double yaw0, const EstimatorOptions& opt) {
  // The reference frame becomes the world frame: gravity along -z, and position and yaw of the
  // oldest frame continue the trajectory from before a reset (or start at the origin).
  const std::vector<Eigen::Isometry3d>& T_ref_body = start.T_ref_body;
  const Eigen::Matrix3d R_w_ref = worldFromGravity(start.g_ref, T_ref_body[0].rotation(), yaw0);
  const Eigen::Vector3d shift = p0 - R_w_ref * T_ref_body[0].translation();
  FrameWindow& window = state.frames;
  for (size_t k = 0; k < window.size(); ++k) {
    WindowSlot& s = window[k];
    s.setPose(R_w_ref * T_ref_body[k].translation() + shift,
              Eigen::Quaterniond(R_w_ref * T_ref_body[k].rotation()));
    s.setV(R_w_ref * start.v_ref[k]);
    s.setBiases(Eigen::Vector3d::Zero(), start.bg);
  }
  StartPrior& prior = state.start_prior;
  prior.mean.setZero();
  prior.mean.head<3>() = window.front().v();
  prior.mean.tail<3>() = start.bg;
  prior.sigma << Eigen::Vector3d::Constant(1.0),  // velocity: weak, the IMU factors decide
      Eigen::Vector3d::Constant(opt.init_acc_bias_sigma_m_s2),
      Eigen::Vector3d::Constant(opt.init_gyr_bias_sigma_rad_s);
  prior.active = true;
}

}  // namespace rgbdi::estimator
