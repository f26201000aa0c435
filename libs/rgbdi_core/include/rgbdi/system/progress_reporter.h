// The progress line of long runs: a MeasurementSink that forwards every measurement to the
// system it watches and, at most every `interval_s` of wall time, rewrites one status line
// (percent, frames, rate, ETA, stream time, odometry state, keyframes, loops). Other log lines
// must call endLine() first so that they do not share the progress line. A live run has no
// fraction or ETA: setLiveStatus() replaces them by the elapsed time and the source's own
// status (rates, drops, latency).
#pragma once

#include <chrono>
#include <functional>
#include <ostream>
#include <string>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

class ProgressReporter : public MeasurementSink {
 public:
  /// `fraction` returns the part of the input read so far (0..1), e.g. RawlogSource::progress.
  ProgressReporter(SlamSystem& system, std::ostream& os, bool quiet, double interval_s,
                   std::function<double()> fraction);

  /// Live mode: the line shows the wall time since the start and `status()` instead of the
  /// percentage and the ETA. `status` is called from the feeding thread.
  void setLiveStatus(std::function<std::string()> status);

  void feedImu(const ImuSample& imu) override;
  void feedRgbd(const RgbdFrame& frame) override;
  void endOfStream() override;

  /// Prints the line now (also when quiet is false and the interval has not passed).
  void update(bool force);
  /// Ends the progress line (a newline if one is on screen).
  void endLine();

  double firstStamp() const { return t0_; }
  double lastStamp() const { return t_last_; }
  std::size_t framesSeen() const { return frames_; }

 private:
  using Clock = std::chrono::steady_clock;
  SlamSystem& system_;
  std::ostream& os_;
  bool quiet_;
  double interval_s_;
  std::function<double()> fraction_;
  std::function<std::string()> live_status_;
  Clock::time_point start_, last_;
  bool on_screen_ = false;
  double t0_, t_last_;
  std::size_t frames_ = 0;
};

}  // namespace rgbdi::system
