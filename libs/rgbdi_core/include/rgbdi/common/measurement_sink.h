// The push interface between sensor sources (rawlog reader, simulator, live grabber) and
// consumers (the odometry, converters, statistics). Sources deliver measurements in
// non-decreasing timestamp order across all kinds.
#pragma once

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi {

class MeasurementSink {
 public:
  virtual ~MeasurementSink() = default;
  virtual void feedImu(const ImuSample& imu) = 0;
  virtual void feedRgbd(const RgbdFrame& frame) = 0;
  /// Wheel odometry; a consumer that has no use for it keeps this default, which drops it (a
  /// sink that passes measurements on must pass these on too).
  virtual void feedWheel(const WheelOdometrySample& /*wheel*/) {}
  /// Called once after the last measurement (end of file, Ctrl-C, or sensor closed).
  virtual void endOfStream() {}
};

}  // namespace rgbdi
