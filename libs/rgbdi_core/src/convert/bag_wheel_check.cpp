#include "rgbdi/convert/bag_wheel_check.h"

#include "rgbdi/io/stream_checker.h"
#include "rgbdi/io/time_ordering_buffer.h"

namespace rgbdi::convert {
namespace {

/// Orders the IMU samples and wheel readings by stamp (the windows of [stream]) and hands them to
/// the checker, as RawlogSource does for a rawlog's records.
class CheckingSink : public bag::ConversionSink {
 public:
  CheckingSink(const std::string& source, const io::StreamConfig& config)
      : buffer_(config.stream.imu_reorder_window_s, config.stream.image_reorder_window_s),
        checker_(source, config) {}

  void imu(const ImuSample& s) override { offer(s, io::MeasurementKind::Imu, s.t); }
  void wheel(const WheelOdometrySample& w) override { offer(w, io::MeasurementKind::Wheel, w.t); }
  void accelerometer(double, const Eigen::Vector3d&) override {}  // no gyroscope: not an IMU
  void frame(const RgbdFrame&) override {}
  void groundTruth(const StampedPose&) override {}

  io::StreamDiagnostics finish(const bag::ConversionReport& report) {
    buffer_.finish();
    drain();
    io::StreamDiagnostics& c = checker_.counters();
    c.records = records_;
    c.observations = records_;
    c.unusable = report.unreadable;
    for (const std::string& w : report.listedIssues("unreadable")) c.warnings.push_back(w);
    c.error = report.error;
    checker_.finish();
    return checker_.diagnostics();
  }

 private:
  void offer(io::Measurement m, io::MeasurementKind kind, double t) {
    const double newest = buffer_.newest(kind);
    const io::TimeOrderingBuffer::Verdict v = buffer_.push(std::move(m), records_);
    checker_.onArrival(kind, t, records_, v, newest);
    ++records_;
    drain();
  }
  void drain() {
    io::TimeOrderingBuffer::Item it;
    while (buffer_.pop(it)) checker_.onDelivered(it.m, it.record);
  }

  io::TimeOrderingBuffer buffer_;
  io::StreamChecker checker_;
  std::size_t records_ = 0;
};

}  // namespace

io::StreamDiagnostics checkBagWheels(const std::string& path, const ConversionSettings& settings,
                                     const bag::TopicOverrides& topics,
                                     const io::StreamConfig& config) {
  bag::BagInputOptions in;
  in.topics = topics;
  in.motion_only = true;
  bag::BagConverter conv(path, settings.options, in, settings.calibration);
  CheckingSink sink(path, config);
  const bag::ConversionReport report = conv.run(sink);
  return sink.finish(report);
}

}  // namespace rgbdi::convert
