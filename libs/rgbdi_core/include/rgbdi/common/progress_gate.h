// When a tool prints its progress line. On a terminal the line is redrawn in place ('\r') at
// most every `interval_s` of wall time. In a log (stderr redirected to a file or a pipe) every
// line stays, so one per second would bury the rest of the log: there a line is due only when
// the work done crosses the next step of `log_step` (0.1: at 10 %, 20 %, ..., 100 %), at most
// 1 / log_step lines whatever the run's length.
#pragma once

namespace rgbdi {

class ProgressGate {
 public:
  /// `interactive`: the stream is a terminal. `interval_s` [s] > 0, `log_step` in (0, 1].
  ProgressGate(bool interactive, double interval_s, double log_step = 0.1);

  /// True when the line for `fraction` (of the work, 0..1) should be printed at wall time
  /// `now_s` [s, any origin]; a true answer counts as printed.
  bool due(double fraction, double now_s);

  bool interactive() const { return interactive_; }

 private:
  bool interactive_;
  double interval_s_;
  double log_step_;
  double last_s_;
  bool started_ = false;
  long last_step_ = 0;  ///< log mode: the last step printed (0: none yet)
};

}  // namespace rgbdi
