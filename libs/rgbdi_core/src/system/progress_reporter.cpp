#include "rgbdi/system/progress_reporter.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace rgbdi::system {

ProgressReporter::ProgressReporter(SlamSystem& system, std::ostream& os, bool quiet,
                                   double interval_s, std::function<double()> fraction)
    : system_(system),
      os_(os),
      quiet_(quiet),
      interval_s_(interval_s),
      fraction_(std::move(fraction)),
      start_(Clock::now()),
      last_(start_),
      t0_(NAN),
      t_last_(NAN) {}

void ProgressReporter::setLiveStatus(std::function<std::string()> status) {
  live_status_ = std::move(status);
}

void ProgressReporter::feedImu(const ImuSample& imu) {
  if (std::isnan(t0_)) t0_ = imu.t;
  t_last_ = imu.t;
  system_.feedImu(imu);
}

void ProgressReporter::feedRgbd(const RgbdFrame& frame) {
  if (std::isnan(t0_)) t0_ = frame.t;
  t_last_ = frame.t;
  ++frames_;
  system_.feedRgbd(frame);
  update(false);
}

void ProgressReporter::endOfStream() {
  system_.endOfStream();
  update(true);
  endLine();
}

void ProgressReporter::update(bool force) {
  if (quiet_) return;
  const auto now = Clock::now();
  if (!force && std::chrono::duration<double>(now - last_).count() < interval_s_) return;
  last_ = now;
  const double wall = std::chrono::duration<double>(now - start_).count();
  const SlamProgress p = system_.progress();
  std::ostringstream line;
  line << std::fixed << std::setprecision(1) << "\r[rgbdi-slam] ";
  if (live_status_) {
    line << "live " << wall << " s, " << estimator::toString(p.status) << ", " << p.keyframes
         << " keyframes, " << p.loops_accepted << " loops, " << live_status_();
  } else {
    const double fraction = fraction_ ? fraction_() : 0.0;
    line << 100.0 * fraction << " %, " << frames_ << " frames, "
         << (wall > 0 ? frames_ / wall : 0.0) << " frames/s, ETA ";
    if (fraction > 0.01)
      line << std::setprecision(0) << wall * (1.0 - fraction) / fraction << " s";
    else
      line << "?";
    line << std::setprecision(1) << ", stream " << (std::isnan(t0_) ? 0.0 : t_last_ - t0_) << " s, "
         << estimator::toString(p.status) << ", " << p.keyframes << " keyframes, "
         << p.loops_accepted << " loops";
  }
  if (p.map_state != MapState::kNoMap) line << ", map: " << toString(p.map_state);
  line << "   ";
  os_ << line.str() << std::flush;
  on_screen_ = true;
}

void ProgressReporter::endLine() {
  if (on_screen_) os_ << "\n";
  on_screen_ = false;
}

}  // namespace rgbdi::system
