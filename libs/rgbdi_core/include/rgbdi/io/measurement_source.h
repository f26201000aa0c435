// The source side of the measurement stream: one interface for rawlogs, converted datasets and
// live sensors. A source yields measurements in non-decreasing time order across all kinds,
// either pulled one at a time (next) or pushed into a MeasurementSink (pump).
#pragma once

#include <atomic>
#include <variant>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/common/types.h"
#include "rgbdi/io/stream_diagnostics.h"

namespace rgbdi::io {

/// One element of the stream.
using Measurement = std::variant<ImuSample, RgbdFrame, WheelOdometrySample>;

/// The kinds of measurement, in the order equal stamps are delivered: a frame's IMU and wheel
/// intervals are complete when the frame arrives.
enum class MeasurementKind { Imu = 0, Wheel = 1, Rgbd = 2 };
constexpr int kMeasurementKinds = 3;

inline double measurementTime(const Measurement& m) {
  return std::visit([](const auto& x) { return x.t; }, m);
}
inline bool isImu(const Measurement& m) { return std::holds_alternative<ImuSample>(m); }
inline bool isWheel(const Measurement& m) { return std::holds_alternative<WheelOdometrySample>(m); }
inline MeasurementKind kindOf(const Measurement& m) {
  if (isImu(m)) return MeasurementKind::Imu;
  return isWheel(m) ? MeasurementKind::Wheel : MeasurementKind::Rgbd;
}
/// "IMU", "wheel odometry", "RGB-D": for messages.
inline const char* kindName(MeasurementKind k) {
  return k == MeasurementKind::Imu     ? "IMU"
         : k == MeasurementKind::Wheel ? "wheel odometry"
                                       : "RGB-D";
}

class MeasurementSource {
 public:
  virtual ~MeasurementSource() = default;

  /// Next measurement in time order; false at the end of the stream. A source that meets
  /// unreadable data first delivers everything read before it, then throws (once).
  virtual bool next(Measurement& out) = 0;
  /// Stop reading new data: later next() calls drain what is buffered, then return false.
  virtual void stopReading() = 0;
  /// Counts and checks of the stream so far (complete once next() has returned false or thrown).
  virtual const StreamDiagnostics& diagnostics() const = 0;

  /// Pushes every measurement into `sink`, then calls sink.endOfStream() exactly once (also when
  /// reading fails: the error is rethrown after endOfStream). When `stop` becomes true the source
  /// stops reading, delivers what it has buffered and ends the stream.
  void pump(MeasurementSink& sink, const std::atomic<bool>* stop = nullptr);
};

}  // namespace rgbdi::io
