#include "rgbdi/io/frame_rate_limiter.h"

#include <cmath>

namespace rgbdi::io {

namespace {
// Fraction of the limit's period two used frames may be closer than it: stamp jitter of a camera
// running exactly at the limit (D435i colour stamps jitter by about a millisecond at 33 ms).
constexpr double kSpacingSlack = 0.9;
}  // namespace

FrameRateLimiter::FrameRateLimiter(double max_rate_hz)
    : min_spacing_s_(max_rate_hz > 0.0 ? kSpacingSlack / max_rate_hz : 0.0) {}

bool FrameRateLimiter::admit(double t) {
  if (min_spacing_s_ <= 0.0 || !std::isfinite(t)) return true;
  if (have_last_ && std::abs(t - last_t_) < min_spacing_s_) {
    ++skipped_;
    return false;
  }
  have_last_ = true;
  last_t_ = t;
  return true;
}

}  // namespace rgbdi::io
