// Latency of a live run at the SLAM system's end: for every image, wall time at which its pose
// left the odometry minus the image's sensor stamp (stamp -> pose), and minus the time the
// source handed the image to the system (delivery -> pose: queue wait + tracking + estimation).
// Together with the source's stamp -> delivery figures (live::LiveStats) these are the stages of
// the end-to-end latency. Bounded memory: histograms, and at most `max_pending` delivered images
// waiting for their pose (older ones are forgotten: the odometry gives no pose to an image it
// skipped or one seen while initialising).
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>

#include "rgbdi/live/latency_histogram.h"

namespace rgbdi::system {

class PoseLatencyMeter {
 public:
  /// `bin_s`, `range_s`: histogram resolution and range [s] (see live::LatencyHistogram).
  PoseLatencyMeter(double bin_s, double range_s, std::size_t max_pending);

  /// The image stamped `t_image` [s] was handed to the system at `wall_s` [s] (same clock as
  /// the stamps). Called in stamp order.
  void delivered(double t_image, double wall_s);
  /// The pose of the image stamped `t_image` came out at `wall_s`. Thread-safe towards
  /// delivered().
  void posed(double t_image, double wall_s);

  struct Summary {
    live::LatencySummary stamp_to_pose;     ///< every pose
    live::LatencySummary delivery_to_pose;  ///< poses whose delivery was recorded
  };
  Summary summary() const;

 private:
  struct Pending {
    double t_image, wall_s;
  };
  std::size_t max_pending_;
  mutable std::mutex mutex_;
  std::deque<Pending> pending_;
  live::LatencyHistogram stamp_to_pose_, delivery_to_pose_;
};

}  // namespace rgbdi::system
