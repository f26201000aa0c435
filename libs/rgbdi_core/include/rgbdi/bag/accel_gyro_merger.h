// Merges separate accelerometer and gyroscope streams (RealSense: Accel_0 and Gyro_0 at different
// rates) into combined IMU samples on the gyro timestamps: the acceleration is interpolated
// linearly between the two accelerometer samples around each gyro stamp. Gyro samples outside the
// accelerometer's span, or inside a gap longer than `max_accel_gap_s`, are dropped and counted.
// Memory is bounded: a gyro sample waits for its later accelerometer sample at most `max_wait_s`
// of newer data (then it is dropped).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <deque>
#include <utility>

#include "rgbdi/common/types.h"

namespace rgbdi::bag {

struct AccelGyroMergeStats {
  std::size_t accel_in = 0, gyro_in = 0, merged = 0;
  std::size_t gyro_before_accel = 0;  ///< gyro samples older than the first accelerometer sample
  std::size_t gyro_after_accel = 0;   ///< newer than the last one (or waited too long)
  std::size_t gyro_in_accel_gap = 0;  ///< bracketing accelerometer samples too far apart
  std::size_t out_of_order = 0;       ///< samples older than one already used (dropped)
  std::size_t dropped() const {
    return gyro_before_accel + gyro_after_accel + gyro_in_accel_gap + out_of_order;
  }
};

class AccelGyroMerger {
 public:
  AccelGyroMerger(double max_accel_gap_s, double max_wait_s);

  void pushAccel(double t, const Eigen::Vector3d& acc);
  void pushGyro(double t, const Eigen::Vector3d& gyr);
  /// No more input: pending gyro samples are resolved (merged or dropped).
  void finish();
  /// Next merged sample in gyro-time order; false when none is ready.
  bool pop(ImuSample& out);

  const AccelGyroMergeStats& stats() const { return stats_; }

 private:
  using Sample = std::pair<double, Eigen::Vector3d>;
  void process();

  double max_gap_, max_wait_;
  std::deque<Sample> accel_, gyro_;
  std::deque<ImuSample> ready_;
  double newest_ = 0.0;
  double consumed_accel_t_ = 0.0, emitted_gyro_t_ = 0.0;
  bool any_input_ = false, accel_popped_ = false, any_gyro_out_ = false, finished_ = false;
  AccelGyroMergeStats stats_;
};

}  // namespace rgbdi::bag
