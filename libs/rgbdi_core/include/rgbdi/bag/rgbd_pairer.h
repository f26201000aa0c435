// Pairs colour and depth images by timestamp, streaming, with bounded memory.
//
// Rule: a colour image c and a depth image d form a frame when |t_c - t_d| <= tolerance, d is
// the nearest depth image to c and c the nearest colour image to d (ties: the earlier one), and
// pairs never cross in time (an image skipped over by a pair is left unpaired). Images without a
// partner come out alone, so that the caller can count them and keep depth-only frames.
// An image is decided once the other stream has passed its stamp by more than the tolerance, or
// once any image `max_wait_s` newer has arrived (a stalled stream), or at finish().
#pragma once

#include <cstddef>
#include <deque>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "rgbdi/common/types.h"

namespace rgbdi::bag {

struct StampedImage {
  double t = 0.0;
  cv::Mat image;
  double unit_m = 0.0;  ///< depth: metres per unit
  std::string label;    ///< where it came from, for messages
};

/// A pair, or a single image that found no partner.
struct PairedImages {
  std::optional<StampedImage> color, depth;
};

struct PairingStats {
  std::size_t pairs = 0, color_alone = 0, depth_alone = 0;
};

class RgbdPairer {
 public:
  RgbdPairer(double tolerance_s, double max_wait_s);

  void pushColor(StampedImage image);
  void pushDepth(StampedImage image);
  /// No more input: everything buffered is decided.
  void finish();
  /// The next decided pair or single image; false when none is ready.
  bool pop(PairedImages& out);

  const PairingStats& stats() const { return stats_; }
  std::size_t buffered() const { return queue_[0].size() + queue_[1].size(); }

 private:
  void push(int stream, StampedImage image);
  void process();
  bool decided(int stream, double t) const;
  /// Index of the image of `stream` nearest to t within the tolerance, or -1.
  long nearest(int stream, double t) const;
  void emitAlone(int stream, StampedImage image);

  double tolerance_, max_wait_;
  std::deque<StampedImage> queue_[2];  ///< 0 = colour, 1 = depth; sorted by stamp
  double latest_[2] = {0.0, 0.0};
  bool seen_[2] = {false, false};
  double newest_ = 0.0;
  bool finished_ = false;
  std::deque<PairedImages> ready_;
  PairingStats stats_;
};

/// The RgbdFrame a pair makes: stamp (the colour image's when there is one), images, depth unit
/// and label. nullopt for colour alone, and for depth alone when `require_colour` (then counted in
/// `*depth_alone_dropped`). Index and calibration are left to the caller.
std::optional<RgbdFrame> frameFromPair(PairedImages pair, bool require_colour,
                                       std::size_t* depth_alone_dropped);

}  // namespace rgbdi::bag
