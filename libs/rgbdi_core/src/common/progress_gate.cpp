#include "rgbdi/common/progress_gate.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rgbdi {

ProgressGate::ProgressGate(bool interactive, double interval_s, double log_step)
    : interactive_(interactive), interval_s_(interval_s), log_step_(log_step), last_s_(0.0) {
  if (!(interval_s > 0.0)) throw std::invalid_argument("ProgressGate: interval_s must be > 0");
  if (!(log_step > 0.0 && log_step <= 1.0))
    throw std::invalid_argument("ProgressGate: log_step must be in (0, 1]");
}

bool ProgressGate::due(double fraction, double now_s) {
  if (interactive_) {
    // The first call starts the clock: the first line comes one interval after the start.
    if (!started_) {
      started_ = true;
      last_s_ = now_s;
      return false;
    }
    if (now_s - last_s_ < interval_s_) return false;
    last_s_ = now_s;
    return true;
  }
  if (!(fraction >= 0.0)) return false;  // NaN or negative: nothing known yet
  // The small margin keeps 0.7 / 0.1 = 6.999999999999999 at step 7.
  const long step = static_cast<long>(std::floor(std::min(fraction, 1.0) / log_step_ + 1e-9));
  if (step <= last_step_) return false;
  last_step_ = step;
  return true;
}

}  // namespace rgbdi
