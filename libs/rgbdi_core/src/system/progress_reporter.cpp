#include "rgbdi/system/progress_reporter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace rgbdi::system {

ProgressReporter::ProgressReporter(SlamSystem& system, std::ostream& os, bool quiet,
                                   double interval_s, std::function<double()> fraction)
    : ProgressReporter(
          system, [&system] { return system.progress(); }, os, quiet, interval_s,
          std::move(fraction)) {}

ProgressReporter::ProgressReporter(MeasurementSink& sink, std::function<SlamProgress()> snapshot,
                                   std::ostream& os, bool quiet, double interval_s,
                                   std::function<double()> fraction)
    : sink_(sink),
      snapshot_(std::move(snapshot)),
      os_(os),
      quiet_(quiet),
      interval_s_(interval_s),
      fraction_(std::move(fraction)),
      start_(Clock::now()),
      last_(start_),
      log_gate_(false, interval_s > 0.0 ? interval_s : 1.0),
      t0_(NAN),
      t_last_(NAN) {}

double ProgressReporter::odometryFraction(double t0, double t_odometry, double t_read,
                                          double read_fraction) {
  if (!std::isfinite(t0) || !std::isfinite(t_odometry) || !std::isfinite(t_read) ||
      !(read_fraction > 0.0))
    return 0.0;
  const double read_span = t_read - t0;
  if (!(read_span > 0.0)) return read_fraction >= 1.0 ? 1.0 : 0.0;
  const double span = read_fraction >= 1.0 ? read_span : read_span / read_fraction;
  return std::clamp((t_odometry - t0) / span, 0.0, 1.0);
}

void ProgressReporter::setLiveStatus(std::function<std::string()> status) {
  live_status_ = std::move(status);
}

void ProgressReporter::setInteractive(bool interactive) { interactive_ = interactive; }

void ProgressReporter::feedImu(const ImuSample& imu) {
  if (std::isnan(t0_)) t0_ = imu.t;
  t_last_ = imu.t;
  sink_.feedImu(imu);
}

void ProgressReporter::feedRgbd(const RgbdFrame& frame) {
  if (std::isnan(t0_)) t0_ = frame.t;
  t_last_ = frame.t;
  ++frames_;
  sink_.feedRgbd(frame);
  update(false);
}

void ProgressReporter::endOfStream() {
  sink_.endOfStream();
  ended_ = true;
  update(true);
  endLine();
}

void ProgressReporter::update(bool force) {
  if (quiet_) return;
  const auto now = Clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_s_) return;
  last_ = now;
  const double wall = std::chrono::duration<double>(now - start_).count();
  const SlamProgress p = snapshot_();
  // At the end the odometry has processed all that was read: the whole input, or up to where a
  // Ctrl-C stopped the reader.
  const double read = fraction_ ? fraction_() : 0.0;
  const double fraction =
      ended_ && read >= 1.0 ? 1.0 : odometryFraction(t0_, p.last_frame_t, t_last_, read);
  const bool log_lines = !interactive_ && !live_status_;
  if (log_lines) {
    // A line per tenth; the final one unless that tenth's line said the same.
    const bool due = log_gate_.due(fraction, wall);
    if (!due && !(force && fraction != logged_fraction_)) return;
    logged_fraction_ = fraction;
  }
  std::ostringstream line;
  line << std::fixed << std::setprecision(1) << (log_lines ? "" : "\r") << "[rgbdi-slam] ";
  if (live_status_) {
    line << "live " << wall << " s, " << estimator::toString(p.status) << ", " << p.keyframes
         << " keyframes, " << p.loops_accepted << " loops, " << live_status_();
  } else {
    line << 100.0 * fraction << " %, " << p.frames << " frames, "
         << (wall > 0 ? p.frames / wall : 0.0) << " frames/s, ETA ";
    if (fraction > 0.01)
      line << std::setprecision(0) << wall * (1.0 - fraction) / fraction << " s";
    else
      line << "?";
    const double stream_s =
        std::isnan(t0_) || std::isnan(p.last_frame_t) ? 0.0 : std::max(0.0, p.last_frame_t - t0_);
    line << std::setprecision(1) << ", stream " << stream_s << " s, "
         << estimator::toString(p.status) << ", " << p.keyframes << " keyframes, "
         << p.loops_accepted << " loops";
  }
  if (p.map_state != MapState::kNoMap) line << ", map: " << toString(p.map_state);
  if (p.map_state == MapState::kNotLocalised && !p.geo_outcome.empty())
    line << " (geometry: " << p.geo_outcome << ", " << p.geo_places << " places)";
  if (log_lines) {
    os_ << line.str() << "\n" << std::flush;  // a line of its own: nothing to end later
    return;
  }
  line << "   ";  // covers the end of a longer previous line
  os_ << line.str() << std::flush;
  on_screen_ = true;
}

void ProgressReporter::endLine() {
  if (on_screen_) os_ << "\n";
  on_screen_ = false;
}

}  // namespace rgbdi::system
