// StreamChecker's wheel-odometry part: counts, rate and gaps of the readings, and the check that
// the wheels do not report motion while the IMU is at rest (slip, a lifted robot, a stream of
// another robot or with the wrong stamps).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rgbdi/io/stream_checker.h"

namespace rgbdi::io {
namespace {

std::string num(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string gnum(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

double wrapAngle(double a) { return std::remainder(a, 2.0 * M_PI); }

}  // namespace

void StreamChecker::onImuForWheelCheck(const ImuSample& s) {
  rest_imu_.push_back(s);
  while (!rest_imu_.empty() && rest_imu_.front().t < s.t - cfg_.stream.wheel_rest_window_s)
    rest_imu_.pop_front();
}

void StreamChecker::onWheelDelivered(const WheelOdometrySample& w, std::size_t record) {
  SensorStreamStats& st = diag_.wheel;
  if (st.delivered == 0) st.first_t = w.t;
  ++st.delivered;
  st.last_t = w.t;
  wheel_stamps_.emplace_back(w.t, record);
  if (w.has_velocities) ++diag_.wheel_with_velocities;
  if (w.has_encoders) ++diag_.wheel_with_encoders;

  // The window [w.t - W, w.t]: its first wheel reading is the newest one at or before its start.
  const double W = cfg_.stream.wheel_rest_window_s;
  rest_wheel_.push_back(w);
  while (rest_wheel_.size() >= 2 && rest_wheel_[1].t <= w.t - W) rest_wheel_.pop_front();
  const WheelOdometrySample& w0 = rest_wheel_.front();
  const double dt = w.t - w0.t;
  while (!rest_imu_.empty() && rest_imu_.front().t < w.t - W) rest_imu_.pop_front();
  const bool enough =
      dt >= 0.5 * W && rest_imu_.size() >= 5 && rest_imu_.back().t - rest_imu_.front().t >= 0.5 * W;
  if (!enough) {
    closeWheelMotionRun();
    return;
  }
  Eigen::Vector3d gyr_sum = Eigen::Vector3d::Zero();
  double acc_sum = 0.0, acc_sq = 0.0;
  for (const ImuSample& s : rest_imu_) {
    gyr_sum += s.gyr;
    const double a = s.acc.norm();
    acc_sum += a;
    acc_sq += a * a;
  }
  const double n = static_cast<double>(rest_imu_.size());
  const double acc_mean = acc_sum / n;
  const double acc_std = std::sqrt(std::max(0.0, acc_sq / n - acc_mean * acc_mean));
  const bool imu_at_rest = (gyr_sum / n).norm() < cfg_.stream.wheel_rest_gyr_rad_s &&
                           acc_std < cfg_.stream.wheel_rest_acc_std_m_s2;
  const double speed = std::hypot(w.x_m - w0.x_m, w.y_m - w0.y_m) / dt;
  const double yaw_rate = std::abs(wrapAngle(w.yaw_rad - w0.yaw_rad)) / dt;
  const bool wheels_move =
      speed > cfg_.stream.wheel_rest_speed_m_s || yaw_rate > cfg_.stream.wheel_rest_yaw_rate_rad_s;
  if (!(imu_at_rest && wheels_move)) {
    closeWheelMotionRun();
    return;
  }
  if (!wheel_run_.open) {
    wheel_run_.open = true;
    wheel_run_.first_record = record;
    wheel_run_.first_t = w0.t;
    wheel_run_.max_speed_m_s = 0.0;
  }
  wheel_run_.last_t = w.t;
  wheel_run_.max_speed_m_s = std::max(wheel_run_.max_speed_m_s, speed);
}

void StreamChecker::closeWheelMotionRun() {
  if (!wheel_run_.open) return;
  wheel_run_.open = false;
  const double span = wheel_run_.last_t - wheel_run_.first_t;
  ++diag_.wheel_moving_at_rest;
  diag_.wheel_moving_at_rest_s += span;
  issue("wheel moves at rest", wheel_run_.first_record,
        at(wheel_run_.first_record) + ": wheel odometry moves (up to " +
            num(wheel_run_.max_speed_m_s, 3) +
            " m/s) while the IMU is at rest, t = " + num(wheel_run_.first_t, 6) + " .. " +
            num(wheel_run_.last_t, 6) + " s (" + num(span, 3) +
            " s; [stream] wheel_rest_*): slip, a lifted robot, or odometry "
            "stamped on another clock?");
}

void StreamChecker::finishWheel() {
  closeWheelMotionRun();
  SensorStreamStats& st = diag_.wheel;
  if (st.delivered == 0) return;  // wheel odometry is optional: its absence is no issue
  st.duration_s = st.last_t - st.first_t;
  if (wheel_stamps_.size() < 2 || st.duration_s <= 0.0) return;
  st.rate_hz = static_cast<double>(st.delivered - 1) / st.duration_s;
  std::vector<double> dts;
  dts.reserve(wheel_stamps_.size() - 1);
  for (std::size_t i = 1; i < wheel_stamps_.size(); ++i)
    dts.push_back(wheel_stamps_[i].first - wheel_stamps_[i - 1].first);
  std::vector<double> sorted = dts;
  auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  st.median_period_s = *mid;
  st.gap_limit_s = cfg_.stream.wheel_gap_factor * st.median_period_s;
  for (std::size_t i = 0; i < dts.size(); ++i) {
    st.max_gap_s = std::max(st.max_gap_s, dts[i]);
    if (dts[i] <= st.gap_limit_s) continue;
    ++st.gaps;
    const std::size_t record = wheel_stamps_[i + 1].second;
    issue("wheel gap", record,
          at(record) + ": wheel-odometry gap of " + num(dts[i], 4) + " s between t = " +
              num(wheel_stamps_[i].first, 6) + " s and t = " + num(wheel_stamps_[i + 1].first, 6) +
              " s (limit " + num(st.gap_limit_s, 4) + " s = wheel_gap_factor " +
              gnum(cfg_.stream.wheel_gap_factor) + " x median period " +
              num(st.median_period_s, 4) + " s)");
  }
}

}  // namespace rgbdi::io
