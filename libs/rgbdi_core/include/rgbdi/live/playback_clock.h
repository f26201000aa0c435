// Real-time pacing of recorded or simulated data: maps wall-clock time to the data's own time
// scale (`speed` data seconds per wall second) from the moment playback starts, and optionally
// re-stamps data onto the wall clock (so that latency from stamp to use can be measured as for a
// real sensor).
#pragma once

#include <stdexcept>

namespace rgbdi::live {

class PlaybackClock {
 public:
  /// `speed` > 0 (1 = real time); `restamp`: stamps become wall-clock times.
  PlaybackClock(double speed, bool restamp) : speed_(speed), restamp_(restamp) {
    if (!(speed > 0.0)) throw std::invalid_argument("PlaybackClock: speed must be > 0");
  }

  /// Playback starts now (`wall_s`, UNIX seconds) at data time `data_t0_s`.
  void start(double wall_s, double data_t0_s) {
    wall0_ = wall_s;
    t0_ = data_t0_s;
    started_ = true;
  }
  bool started() const { return started_; }

  /// [s] newest data stamp that is due at wall time `wall_s`.
  double horizon(double wall_s) const { return t0_ + (wall_s - wall0_) * speed_; }
  /// [s] wall time at which data stamped `t` is due.
  double dueWall(double t) const { return wall0_ + (t - t0_) / speed_; }
  /// The stamp the data carries on output: its own, or its due wall time.
  double outputStamp(double t) const { return restamp_ ? dueWall(t) : t; }

  double speed() const { return speed_; }
  bool restamp() const { return restamp_; }

 private:
  double speed_;
  bool restamp_;
  double wall0_ = 0.0, t0_ = 0.0;
  bool started_ = false;
};

}  // namespace rgbdi::live
