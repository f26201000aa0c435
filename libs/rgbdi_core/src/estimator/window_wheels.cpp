#include "estimator/window_wheels.h"

#include <algorithm>
#include <cstdlib>

#include "rgbdi/estimator/wheel_calibration_factor.h"
#include "rgbdi/estimator/wheel_factor.h"

namespace rgbdi::estimator {

bool WindowWheels::tickIncrements(double t_a, double t_b, std::int64_t* left,
                                  std::int64_t* right) const {
  // The newest reading at or before t_a and the oldest at or after t_b.
  const WheelOdometrySample* a = nullptr;
  const WheelOdometrySample* b = nullptr;
  for (const WheelOdometrySample& w : readings) {
    const double t = w.t + time_offset[0];
    if (t <= t_a) a = &w;
    if (t >= t_b && !b) b = &w;
  }
  if (!a || !b || !a->has_encoders || !b->has_encoders) return false;
  *left = static_cast<std::int64_t>(b->ticks_left) - a->ticks_left;
  *right = static_cast<std::int64_t>(b->ticks_right) - a->ticks_right;
  return true;
}

WheelVerdict WindowWheels::check(const WheelPreintegration& pre, const double* pose_a,
                                 const double* pose_b, double t_a, double t_b,
                                 const WheelOptions& opt) const {
  if (opt.gate_chi2 <= 0.0) return WheelVerdict::Consistent;
  Eigen::Matrix<double, 6, 1> e;
  Eigen::Vector3d dp;
  if (opt.calibrating()) {
    const WheelCalibrationFactor f(pre, opt.T_body_wheel);
    e = f.error(pose_a, pose_b, scale_v[0], scale_w[0], extrinsic_yaw[0], time_offset[0]);
    dp = pre.calibratedMotion(scale_v[0], scale_w[0], extrinsic_yaw[0],
                              time_offset[0] - pre.cutTimeOffset())
             .dp;
  } else {
    const WheelFactor f(pre, opt.T_body_wheel);
    e = f.error(pose_a, pose_b, scale_v[0], scale_w[0]);
    pre.motion(scale_v[0], scale_w[0], &dp, nullptr);
  }
  if (e.cwiseProduct(pre.sqrtInformation()).squaredNorm() <= opt.gate_chi2)
    return WheelVerdict::Consistent;
  const double wheels_m = dp.norm();
  // The window's own motion in the wheel frame: the error plus what the wheels said.
  const double window_m = (e.head<3>() + dp).norm();
  if (wheels_m < opt.fault_motion_ratio * window_m) return WheelVerdict::Stuck;
  // One wheel's encoder standing while the other turns: a blocked wheel dragged along.
  std::int64_t left = 0, right = 0;
  if (tickIncrements(t_a, t_b, &left, &right)) {
    const std::int64_t lo = std::min(std::abs(left), std::abs(right));
    const std::int64_t hi = std::max(std::abs(left), std::abs(right));
    if (hi > 0 && static_cast<double>(lo) < opt.fault_motion_ratio * static_cast<double>(hi))
      return WheelVerdict::Stuck;
  }
  if (window_m < opt.fault_motion_ratio * wheels_m) return WheelVerdict::Lifted;
  return WheelVerdict::Slip;
}

void WindowWheels::count(WheelVerdict v, double t_a, double t_b) {
  if (v != WheelVerdict::Consistent) {
    if (!episodes.empty() && episodes.back().verdict == v && episodes.back().t_end >= t_a)
      episodes.back().t_end = t_b;
    else
      episodes.push_back({t_a, t_b, v});
  }
  switch (v) {
    case WheelVerdict::Consistent:
      ++intervals_used;
      break;
    case WheelVerdict::Slip:
      ++intervals_slip;
      break;
    case WheelVerdict::Stuck:
      ++intervals_stuck;
      break;
    case WheelVerdict::Lifted:
      ++intervals_lifted;
      break;
  }
}

void WindowWheels::add(const WheelOdometrySample& w) {
  if (!isFinite(w) || (!readings.empty() && w.t <= readings.back().t)) return;
  readings.push_back(w);
}

std::optional<WheelPreintegration> WindowWheels::interval(const WindowSlot& a, const WindowSlot& b,
                                                          const WheelOptions& opt) const {
  const bool three_d = opt.direction_from_gyro == "always" ||
                       (opt.direction_from_gyro == "blind" && b.bridged_s > 0.0);
  if (!three_d || !b.preint)
    return WheelPreintegration::between(readings, a.t, b.t, time_offset[0], opt.noise,
                                        opt.reading_lag_s);
  // The gyroscope's samples of the interval at the older frame's bias (the factors are rebuilt
  // at every update, so the bias follows the solve).
  WheelGyro gyro;
  gyro.samples = &b.preint->samples();
  gyro.bias = a.bg();
  gyro.R_body_wheel = opt.T_body_wheel.rotation();
  return WheelPreintegration::between(readings, a.t, b.t, time_offset[0], opt.noise,
                                      opt.reading_lag_s, &gyro);
}

void WindowWheels::trimBefore(double t, const WheelOptions& opt) {
  // Keep the newest reading at or before t: the interval from t interpolates from it (at the
  // largest offset the estimate may still reach, which cuts the earliest).
  const double td =
      opt.estimate_time_offset ? opt.time_offset_s + opt.time_offset_max_change_s : time_offset[0];
  while (readings.size() >= 2 && readings[1].t + td <= t) readings.pop_front();
}

void WindowWheels::priorDropped() {
  // A pending prior is still the problem's, around its mean.
  if (!scale_prior_pending) {
    scale_prior_pending = true;
    prior_mean_v = scale_v[0];
    prior_mean_w = scale_w[0];
  }
  if (!calib_prior_pending) {
    calib_prior_pending = true;
    prior_mean_yaw = extrinsic_yaw[0];
    prior_mean_td = time_offset[0];
  }
}

void WindowWheels::init(const WheelOptions& opt) {
  time_offset[0] = opt.time_offset_s;
  prior_mean_td = opt.time_offset_s;
}

WheelCalibration WindowWheels::calibration(const WheelOptions& opt) const {
  WheelCalibration c;
  c.scale_v = scale_v[0];
  c.scale_w = scale_w[0];
  c.T_body_wheel = T_body_wheel(opt);
  c.time_offset_s = time_offset[0];
  return c;
}

WheelTerm WindowWheels::factor(const WheelPreintegration& pre, double* pose_a, double* pose_b,
                               const WheelOptions& opt) {
  WheelTerm t;
  if (opt.calibrating()) {
    t.cost = std::make_unique<WheelCalibrationFactor>(pre, opt.T_body_wheel);
    t.blocks = {pose_a, pose_b, scale_v, scale_w, extrinsic_yaw, time_offset};
  } else {
    t.cost = std::make_unique<WheelFactor>(pre, opt.T_body_wheel);
    t.blocks = {pose_a, pose_b, scale_v, scale_w};
  }
  return t;
}

Eigen::Isometry3d WindowWheels::T_body_wheel(const WheelOptions& opt) const {
  if (!opt.estimate_extrinsic_yaw) return opt.T_body_wheel;
  Eigen::Isometry3d T = opt.T_body_wheel;
  T.linear() = opt.T_body_wheel.rotation() *
               Eigen::AngleAxisd(extrinsic_yaw[0], Eigen::Vector3d::UnitZ()).matrix();
  return T;
}

void WindowWheels::clampCalibration(const WheelOptions& opt) {
  extrinsic_yaw[0] =
      std::clamp(extrinsic_yaw[0], -opt.extrinsic_yaw_max_rad, opt.extrinsic_yaw_max_rad);
  time_offset[0] = std::clamp(time_offset[0], opt.time_offset_s - opt.time_offset_max_change_s,
                              opt.time_offset_s + opt.time_offset_max_change_s);
}

}  // namespace rgbdi::estimator
