// [stream] image_rate_limit_hz: which RGB-D frames of a faster camera a source passes on. Sources
// ask before they decode a frame's images, so a skipped frame costs nothing but its record (the
// per-frame decoding and tracking are most of what a 30 Hz stream costs; doc/performance.md).
// The same rule as OpenVINS' track_frequency: a frame is used when it is at least a period
// after the last frame used; the others are skipped for good (they get no pose).
#pragma once

#include <cstddef>

namespace rgbdi::io {

class FrameRateLimiter {
 public:
  /// `max_rate_hz` <= 0: every frame is used.
  explicit FrameRateLimiter(double max_rate_hz);

  /// True when the frame stamped `t` [s] is used: the first frame, and any frame at least 0.9 /
  /// max_rate_hz from the last one used (earlier or later: a frame re-ordered by its source is
  /// judged by the same spacing). The 10 % slack keeps every frame of a camera running at the
  /// limit despite stamp jitter; at a higher camera rate the frames used are a whole number of
  /// camera periods apart (a 30 Hz camera under a 15-29 Hz limit: every second frame). A stamp
  /// that is not finite is passed on (the stream checks drop and report it).
  bool admit(double t);

  /// Frames skipped so far.
  std::size_t skipped() const { return skipped_; }

 private:
  double min_spacing_s_;  ///< [s] 0.9 / max_rate_hz; 0 = no limit
  bool have_last_ = false;
  double last_t_ = 0.0;  ///< [s] stamp of the last frame used
  std::size_t skipped_ = 0;
};

}  // namespace rgbdi::io
