// The progress line of long runs: a MeasurementSink that forwards every measurement to the
// system it watches and, at most every `interval_s` of wall time, rewrites one status line
// (percent, frames, rate, ETA, stream time, odometry state, keyframes, loops). Other log lines
// must call endLine() first so that they do not share the progress line. A live run has no
// fraction or ETA: setLiveStatus() replaces them by the elapsed time and the source's own
// status (rates, drops, latency).
//
// The reader runs ahead of the odometry behind bounded queues (it had read the whole of a 40 s
// stream when the odometry was at 74 %), so the percentage, frame count, rate and ETA follow the
// odometry: the stamp of the last frame it finished against the stream's span, and the frames it
// finished per second of wall time. "stream" is the stream time the odometry has reached.
//
// A log that is not a terminal (setInteractive(false)) keeps every line: there an offline run
// prints one line per tenth of the stream (ProgressGate) and the final one, each ended by '\n',
// as rgbdi-sim and rawlog-convert do. A live run has no fraction and keeps its redrawn line.
#pragma once

#include <chrono>
#include <functional>
#include <ostream>
#include <string>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/common/progress_gate.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

class ProgressReporter : public MeasurementSink {
 public:
  /// `fraction` returns the part of the input read so far (0..1), e.g. RawlogSource::progress.
  ProgressReporter(SlamSystem& system, std::ostream& os, bool quiet, double interval_s,
                   std::function<double()> fraction);
  /// The same with any sink and a snapshot of its progress (tests).
  ProgressReporter(MeasurementSink& sink, std::function<SlamProgress()> snapshot, std::ostream& os,
                   bool quiet, double interval_s, std::function<double()> fraction);

  /// Live mode: the line shows the wall time since the start and `status()` instead of the
  /// percentage and the ETA. `status` is called from the feeding thread.
  void setLiveStatus(std::function<std::string()> status);
  /// false: the stream is a log, not a terminal (see above). Default true.
  void setInteractive(bool interactive);

  void feedImu(const ImuSample& imu) override;
  void feedRgbd(const RgbdFrame& frame) override;
  void feedWheel(const WheelOdometrySample& wheel) override { sink_.feedWheel(wheel); }
  void endOfStream() override;

  /// Prints the line now (also when quiet is false and the interval has not passed).
  void update(bool force);
  /// Ends the progress line (a newline if one is on screen).
  void endLine();

  /// Stamps of the first and last measurement read (the reader's, not the odometry's).
  double firstStamp() const { return t0_; }
  double lastStamp() const { return t_last_; }
  std::size_t framesSeen() const { return frames_; }

  /// Part of the stream the odometry has processed, in [0, 1]: (t_odometry - t0) / span, where
  /// the span is t_read - t0 once the whole input is read (read_fraction = 1) and is extrapolated
  /// as (t_read - t0) / read_fraction before. 0 while anything is unknown (NaN stamps, nothing
  /// read); 1 for a stream of one instant that was read whole.
  static double odometryFraction(double t0, double t_odometry, double t_read, double read_fraction);

 private:
  using Clock = std::chrono::steady_clock;
  MeasurementSink& sink_;
  std::function<SlamProgress()> snapshot_;
  std::ostream& os_;
  bool quiet_;
  double interval_s_;
  std::function<double()> fraction_;
  std::function<std::string()> live_status_;
  Clock::time_point start_, last_;
  bool interactive_ = true;
  ProgressGate log_gate_;          ///< when a log line is due (not interactive)
  double logged_fraction_ = -1.0;  ///< of the last log line (-1: none)
  bool on_screen_ = false;
  bool ended_ = false;  ///< endOfStream has returned: the odometry has processed all it read
  double t0_, t_last_;
  std::size_t frames_ = 0;
};

}  // namespace rgbdi::system
