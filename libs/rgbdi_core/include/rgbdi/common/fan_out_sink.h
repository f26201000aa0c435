// A MeasurementSink that hands every measurement to several sinks in the given order, so one
// pass over a source (a rendered simulation, a rawlog) feeds several consumers: a run and its
// recorder, or two configurations compared on identical input.
#pragma once

#include <utility>
#include <vector>

#include "rgbdi/common/measurement_sink.h"

namespace rgbdi {

class FanOutSink : public MeasurementSink {
 public:
  /// The sinks are not owned and must outlive this object.
  explicit FanOutSink(std::vector<MeasurementSink*> sinks) : sinks_(std::move(sinks)) {}

  void feedImu(const ImuSample& imu) override {
    for (MeasurementSink* s : sinks_) s->feedImu(imu);
  }
  void feedRgbd(const RgbdFrame& frame) override {
    for (MeasurementSink* s : sinks_) s->feedRgbd(frame);
  }
  void feedWheel(const WheelOdometrySample& wheel) override {
    for (MeasurementSink* s : sinks_) s->feedWheel(wheel);
  }
  void endOfStream() override {
    for (MeasurementSink* s : sinks_) s->endOfStream();
  }

 private:
  std::vector<MeasurementSink*> sinks_;
};

}  // namespace rgbdi
