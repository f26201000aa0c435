// StreamChecker's wheel-odometry part: counts, rate and gaps of the readings, the check that the
// wheels do not report motion while the IMU is at rest (slip, a lifted robot, a stream of another
// robot or with the wrong stamps) and its converse, wheels standing while the IMU moves (a
// blocked wheel, a robot pushed or carried).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

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

/// Standard deviation (norm over the axes) of the means of the acceleration vector over
/// consecutive blocks of `block_s` from the first sample: how much the specific force changed,
/// with noise and vibration faster than the blocks averaged out. 0 with fewer than two blocks.
double blockMeanSpread(const std::deque<ImuSample>& imu, double block_s) {
  std::vector<Eigen::Vector3d> means;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  long block = 0;
  for (const ImuSample& s : imu) {
    const long b = static_cast<long>(std::floor((s.t - imu.front().t) / block_s));
    if (b != block && count > 0) {
      means.push_back(sum / count);
      sum.setZero();
      count = 0;
    }
    block = b;
    sum += s.acc;
    ++count;
  }
  if (count > 0) means.push_back(sum / count);
  if (means.size() < 2) return 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& m : means) mean += m;
  mean /= static_cast<double>(means.size());
  double var = 0.0;
  for (const Eigen::Vector3d& m : means) var += (m - mean).squaredNorm();
  return std::sqrt(var / static_cast<double>(means.size()));
}

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
    closeWheelStillRun();
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
  const double gyr_mean = (gyr_sum / n).norm();
  const StreamOptions& o = cfg_.stream;
  const bool imu_at_rest = gyr_mean < o.wheel_rest_gyr_rad_s && acc_std < o.wheel_rest_acc_std_m_s2;
  const double acc_change = blockMeanSpread(rest_imu_, o.wheel_still_block_s);
  const bool imu_moves = gyr_mean > o.wheel_still_gyr_rad_s || acc_change > o.wheel_still_acc_m_s2;
  const double speed = std::hypot(w.x_m - w0.x_m, w.y_m - w0.y_m) / dt;
  const double yaw_rate = std::abs(wrapAngle(w.yaw_rad - w0.yaw_rad)) / dt;
  const bool wheels_move = speed > o.wheel_rest_speed_m_s || yaw_rate > o.wheel_rest_yaw_rate_rad_s;

  if (imu_at_rest && wheels_move) {
    extendRun(wheel_run_, w0.t, w.t, record);
    wheel_run_.peak_a = std::max(wheel_run_.peak_a, speed);
  } else {
    closeWheelMotionRun();
  }
  if (imu_moves && !wheels_move) {
    extendRun(still_run_, w0.t, w.t, record);
    still_run_.peak_a = std::max(still_run_.peak_a, gyr_mean);
    still_run_.peak_b = std::max(still_run_.peak_b, acc_change);
  } else {
    closeWheelStillRun();
  }
}

void StreamChecker::extendRun(WheelCheckRun& run, double first_t, double last_t,
                              std::size_t record) {
  if (!run.open) {
    run = WheelCheckRun();
    run.open = true;
    run.first_record = record;
    run.first_t = first_t;
  }
  run.last_t = last_t;
}

void StreamChecker::wheelIssue(const std::string& kind, std::size_t record,
                               const std::string& message) {
  const std::size_t listed = diag_.warnings.size();
  issue(kind, record, message);
  if (diag_.warnings.size() > listed) diag_.wheel_warnings.push_back(message);
}

void StreamChecker::closeWheelMotionRun() {
  if (!wheel_run_.open) return;
  wheel_run_.open = false;
  const double span = wheel_run_.last_t - wheel_run_.first_t;
  ++diag_.wheel_moving_at_rest;
  diag_.wheel_moving_at_rest_s += span;
  wheelIssue("wheel moves at rest", wheel_run_.first_record,
             at(wheel_run_.first_record) + ": wheel odometry moves (up to " +
                 num(wheel_run_.peak_a, 3) +
                 " m/s) while the IMU is at rest, t = " + num(wheel_run_.first_t, 6) + " .. " +
                 num(wheel_run_.last_t, 6) + " s (" + num(span, 3) +
                 " s; [stream] wheel_rest_*): slip, a lifted robot, or odometry "
                 "stamped on another clock?");
}

void StreamChecker::closeWheelStillRun() {
  if (!still_run_.open) return;
  still_run_.open = false;
  const double span = still_run_.last_t - still_run_.first_t;
  ++diag_.wheel_still_imu_moving;
  diag_.wheel_still_imu_moving_s += span;
  wheelIssue("wheel still while moving", still_run_.first_record,
             at(still_run_.first_record) +
                 ": wheel odometry stands while the IMU moves (mean angular rate up to " +
                 num(still_run_.peak_a, 3) + " rad/s, spread of its acceleration up to " +
                 num(still_run_.peak_b, 3) + " m/s^2), t = " + num(still_run_.first_t, 6) + " .. " +
                 num(still_run_.last_t, 6) + " s (" + num(span, 3) +
                 " s; [stream] wheel_still_*, wheel_rest_speed_m_s / yaw_rate): a blocked "
                 "wheel, a robot pushed or carried, or odometry stamped on another clock?");
}

void StreamChecker::finishWheel() {
  closeWheelMotionRun();
  closeWheelStillRun();
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
    if (dts[i] > st.max_gap_s) {
      st.max_gap_s = dts[i];
      diag_.wheel_max_gap_t = wheel_stamps_[i].first;
    }
    if (dts[i] <= st.gap_limit_s) continue;
    ++st.gaps;
    const std::size_t record = wheel_stamps_[i + 1].second;
    wheelIssue("wheel gap", record,
               at(record) + ": wheel-odometry gap of " + num(dts[i], 4) +
                   " s between t = " + num(wheel_stamps_[i].first, 6) + " s and t = " +
                   num(wheel_stamps_[i + 1].first, 6) + " s (limit " + num(st.gap_limit_s, 4) +
                   " s = wheel_gap_factor " + gnum(cfg_.stream.wheel_gap_factor) +
                   " x median period " + num(st.median_period_s, 4) + " s)");
  }
}

}  // namespace rgbdi::io
