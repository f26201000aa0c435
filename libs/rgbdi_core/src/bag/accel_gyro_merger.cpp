#include "rgbdi/bag/accel_gyro_merger.h"

#include <algorithm>

namespace rgbdi::bag {

AccelGyroMerger::AccelGyroMerger(double max_accel_gap_s, double max_wait_s)
    : max_gap_(max_accel_gap_s), max_wait_(max_wait_s) {}

namespace {

void insertSorted(std::deque<std::pair<double, Eigen::Vector3d>>& q, double t,
                  const Eigen::Vector3d& v) {
  const auto pos = std::upper_bound(
      q.begin(), q.end(), t,
      [](double a, const std::pair<double, Eigen::Vector3d>& s) { return a < s.first; });
  q.insert(pos, {t, v});
}

}  // namespace

void AccelGyroMerger::pushAccel(double t, const Eigen::Vector3d& acc) {
  ++stats_.accel_in;
  // An accelerometer sample older than one already discarded cannot be placed any more.
  if (accel_popped_ && t < consumed_accel_t_) {
    ++stats_.out_of_order;
    return;
  }
  insertSorted(accel_, t, acc);
  newest_ = any_input_ ? std::max(newest_, t) : t;
  any_input_ = true;
  process();
}

void AccelGyroMerger::pushGyro(double t, const Eigen::Vector3d& gyr) {
  ++stats_.gyro_in;
  if (any_gyro_out_ && t <= emitted_gyro_t_) {
    ++stats_.out_of_order;
    return;
  }
  insertSorted(gyro_, t, gyr);
  newest_ = any_input_ ? std::max(newest_, t) : t;
  any_input_ = true;
  process();
}

void AccelGyroMerger::finish() {
  finished_ = true;
  process();
}

void AccelGyroMerger::process() {
  const auto dropOldestAccel = [this]() {
    consumed_accel_t_ = accel_.front().first;
    accel_popped_ = true;
    accel_.pop_front();
  };
  while (!gyro_.empty()) {
    const Sample& g = gyro_.front();
    const bool waited_enough = finished_ || newest_ - g.first > max_wait_;
    // First accelerometer sample at or after the gyro stamp.
    const auto after = std::lower_bound(accel_.begin(), accel_.end(), g.first,
                                        [](const Sample& s, double t) { return s.first < t; });
    if (after == accel_.end() && !waited_enough) return;
    ImuSample s;
    s.t = g.first;
    s.gyr = g.second;
    bool ok = false;
    if (after == accel_.end()) {
      ++(accel_.empty() && !accel_popped_ ? stats_.gyro_before_accel : stats_.gyro_after_accel);
    } else if (after->first == g.first) {
      s.acc = after->second;
      ok = true;
    } else if (after == accel_.begin()) {
      // Nothing older is buffered: either the accelerometer starts later, or this gyro sample
      // arrived after the samples around it were discarded.
      ++(accel_popped_ ? stats_.out_of_order : stats_.gyro_before_accel);
    } else {
      const Sample& a0 = *(after - 1);
      const Sample& a1 = *after;
      if (a1.first - a0.first > max_gap_) {
        ++stats_.gyro_in_accel_gap;
      } else {
        const double w = (g.first - a0.first) / (a1.first - a0.first);
        s.acc = (1.0 - w) * a0.second + w * a1.second;
        ok = true;
      }
    }
    if (ok) {
      ready_.push_back(s);
      ++stats_.merged;
    }
    emitted_gyro_t_ = g.first;
    any_gyro_out_ = true;
    gyro_.pop_front();
    // Keep the accelerometer sample at or before the next gyro stamp and everything after it.
    const double next_t = gyro_.empty() ? emitted_gyro_t_ : gyro_.front().first;
    while (accel_.size() >= 2 && accel_[1].first <= next_t) dropOldestAccel();
  }
  // No gyro sample pending: bound the accelerometer buffer by the waiting time.
  while (accel_.size() >= 2 && accel_[1].first < newest_ - max_wait_) dropOldestAccel();
}

bool AccelGyroMerger::pop(ImuSample& out) {
  if (ready_.empty()) return false;
  out = ready_.front();
  ready_.pop_front();
  return true;
}

}  // namespace rgbdi::bag
