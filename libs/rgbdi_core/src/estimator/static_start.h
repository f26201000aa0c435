// Static start (doc/estimator.md "Initialisation"): the sensor is at rest when, over
// init_static_window_s, the gyro mean, the deviation of |mean specific force| from g, the spread
// of the accelerometer and the motion of the tracked features are small. Then gravity comes from
// the mean specific force, the velocity is zero and the gyro bias is the mean rate: a ground
// robot starts at rest at once.
#pragma once

#include <Eigen/Core>
#include <deque>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::imu {
class ImuBuffer;
}

namespace rgbdi::estimator {

/// The outcome of the stillness test.
struct Stillness {
  const char* failure = nullptr;  ///< why the sensor is not (known to be) at rest; null: at rest
  Eigen::Vector3d mean_acc = Eigen::Vector3d::Zero();  ///< [m/s^2] body frame, over the window
  Eigen::Vector3d mean_gyr = Eigen::Vector3d::Zero();  ///< [rad/s] body frame, over the window
};

/// The recent frames seen while initialising and the stillness test over them. (They are kept
/// apart from the initialisation window, which restarts whenever PnP fails, e.g. always without
/// depth.)
class StaticStart {
 public:
  StaticStart(const EstimatorOptions& opt, const ImuOptions& imu);

  /// Remembers a frame at IMU-clock time `t`: two stillness windows of frames are kept, and
  /// always the previous frame.
  void addFrame(double t, const std::vector<frontend::FeatureObservation>& features);
  void clear() { frames_.clear(); }
  bool empty() const { return frames_.empty(); }
  /// [s] IMU-clock time of the oldest frame remembered (the IMU history the test may need).
  double oldestFrameTime() const { return frames_.front().t; }

  /// Whether the sensor rested up to `frame` (the newest remembered frame, at IMU-clock time
  /// `t`), judged on `imu` and the features' motion.
  Stillness judge(const frontend::FeatureFrame& frame, double t, const imu::ImuBuffer& imu) const;

 private:
  struct Frame {
    double t;  ///< [s] IMU clock
    std::vector<frontend::FeatureObservation> features;
  };

  EstimatorOptions opt_;
  double gravity_m_s2_;
  std::deque<Frame> frames_;
};

}  // namespace rgbdi::estimator
