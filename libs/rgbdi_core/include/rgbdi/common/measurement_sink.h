// The push interface between sensor sources (rawlog reader, simulator, live grabber) and
// consumers (the odometry, converters, statistics). Sources deliver measurements in
// non-decreasing timestamp order across both kinds.
#pragma once

#include "rgbdi/common/types.h"

namespace rgbdi {

class MeasurementSink {
 public:
  virtual ~MeasurementSink() = default;
  virtual void feedImu(const ImuSample& imu) = 0;
  virtual void feedRgbd(const RgbdFrame& frame) = 0;
  /// Called once after the last measurement (end of file, Ctrl-C, or sensor closed).
  virtual void endOfStream() {}
};

}  // namespace rgbdi
