// Accumulates StreamDiagnostics while a source reads its data: arrival-order problems, what is
// delivered (rates, gaps), per-frame checks (sizes, intrinsics, depth units, sensorPose) and
// stream-level checks at the end (image gaps against the median period, IMU units and rate).
// Messages name the source and the record; each kind of issue lists at most
// StreamOptions::max_listed_issues messages, further occurrences are counted and summarised.
#pragma once

#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "rgbdi/io/stream_diagnostics.h"
#include "rgbdi/io/stream_options.h"
#include "rgbdi/io/time_ordering_buffer.h"

namespace rgbdi::io {

class StreamChecker {
 public:
  /// `on_warning` (optional) is called with every listed warning as soon as it is found.
  StreamChecker(std::string source, const StreamConfig& cfg,
                std::function<void(const std::string&)> on_warning = {});

  /// Direct access for the counters the source keeps itself (records, skipped, error, ...).
  StreamDiagnostics& counters() { return diag_; }

  /// A measurement of `kind` stamped `t` offered to the ordering buffer, with the buffer's
  /// verdict and the newest stamp of the same kind before it (NaN if none).
  void onArrival(MeasurementKind kind, double t, std::size_t record,
                 TimeOrderingBuffer::Verdict verdict, double newest_same_kind);
  /// A measurement handed to the consumer.
  void onDelivered(const Measurement& m, std::size_t record);
  /// An RGB-D/IMU observation that could not be converted (message from the converter).
  void onUnusable(std::size_t record, const std::string& why);
  /// An entry of a type the stream does not use.
  void onSkipped(std::size_t record, const std::string& class_name);

  /// Stream-level checks; call once at the end (further calls do nothing).
  void finish();
  const StreamDiagnostics& diagnostics() const { return diag_; }

  /// Prefix of every message: "<source> record <n>".
  std::string at(std::size_t record) const;

 private:
  struct IssueKind {
    std::size_t count = 0;
    std::size_t unlisted = 0;
    std::size_t first_unlisted = 0, last_unlisted = 0;
  };
  /// Lists `message` unless this kind already has max_listed_issues messages.
  void issue(const std::string& kind, std::size_t record, const std::string& message);
  void warn(const std::string& message);
  void checkFrame(const RgbdFrame& f, std::size_t record);
  void checkDepthUnits(const RgbdFrame& f, std::size_t record);
  void checkExtrinsic(const RgbdFrame& f, std::size_t record);
  /// Extends or closes the current run of black/constant colour images.
  void checkConstantColor(const RgbdFrame& f, std::size_t record);
  void closeConstantRun();
  void finishImu();
  void finishImages();
  /// Wheel odometry (stream_checker_wheel.cpp): counts, and the check against the IMU at rest.
  void onWheelDelivered(const WheelOdometrySample& w, std::size_t record);
  void onImuForWheelCheck(const ImuSample& s);
  struct WheelCheckRun;
  /// Opens `run` at (first_t, record) or extends it to last_t.
  static void extendRun(WheelCheckRun& run, double first_t, double last_t, std::size_t record);
  void closeWheelMotionRun();
  void closeWheelStillRun();
  /// issue(), also keeping a listed message in diag_.wheel_warnings.
  void wheelIssue(const std::string& kind, std::size_t record, const std::string& message);
  void finishWheel();
  std::string records(std::size_t a, std::size_t b) const;

  std::string source_;
  StreamConfig cfg_;
  std::function<void(const std::string&)> on_warning_;
  StreamDiagnostics diag_;
  bool finished_ = false;

  std::map<std::string, IssueKind> issues_;
  std::vector<std::string> issue_order_;

  double prev_arrival_[kMeasurementKinds];
  double prev_delivered_imu_t_;
  double acc_norm_sum_ = 0.0;
  std::size_t first_imu_record_ = 0, last_imu_record_ = 0;
  std::size_t first_frame_record_ = 0, last_frame_record_ = 0;
  std::vector<std::pair<double, std::size_t>> frame_stamps_;  ///< (t, record) of delivered frames
  std::vector<double> frame_median_depths_;                   ///< [m] per frame with valid depth
  bool extrinsic_checked_mismatch_ = false;
  struct ConstantRun {
    std::size_t frames = 0;
    std::size_t first_record = 0, last_record = 0;
    double first_t = 0.0, last_t = 0.0;
    int lo = 255, hi = 0;  ///< [grey levels] range of the sampled values over the run
  } constant_run_;

  std::vector<std::pair<double, std::size_t>> wheel_stamps_;  ///< (t, record) delivered
  std::deque<ImuSample> rest_imu_;              ///< IMU of the last wheel_rest_window_s
  std::deque<WheelOdometrySample> rest_wheel_;  ///< wheel readings of that window
  /// A run of consecutive windows with one verdict, and the peak values behind it.
  struct WheelCheckRun {
    bool open = false;
    std::size_t first_record = 0;
    double first_t = 0.0, last_t = 0.0;
    double peak_a = 0.0;  ///< moving at rest: wheel speed [m/s]; still: IMU mean rate [rad/s]
    double peak_b = 0.0;  ///< still: spread of the acceleration's block means [m/s^2]
  };
  WheelCheckRun wheel_run_;  ///< wheels moving while the IMU rests
  WheelCheckRun still_run_;  ///< wheels standing while the IMU moves
};

}  // namespace rgbdi::io
