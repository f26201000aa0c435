// Where a dataset converter delivers what it decodes, in (roughly) time order: the writer behind
// it re-orders within a window and writes the rawlog and the ground truth.
#pragma once

#include <functional>

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::bag {

class ConversionSink {
 public:
  virtual ~ConversionSink() = default;
  virtual void imu(const ImuSample& sample) = 0;
  /// An accelerometer sample without gyroscope data (TUM RGB-D's Kinect accelerometer) [m/s^2].
  virtual void accelerometer(double t, const Eigen::Vector3d& acc) = 0;
  virtual void frame(const RgbdFrame& frame) = 0;
  /// Ground-truth pose of the tracked body in the world frame.
  virtual void groundTruth(const StampedPose& pose) = 0;
  /// A wheel-odometry reading (a bag's nav_msgs/Odometry). A sink with no use for it keeps this
  /// default, which drops it.
  virtual void wheel(const WheelOdometrySample& /*reading*/) {}
};

/// Called often during a conversion with the fraction of the input consumed, in [0, 1].
using ProgressCallback = std::function<void(double fraction)>;

}  // namespace rgbdi::bag
