// Bounded re-ordering of a measurement stream that arrives almost, but not exactly, in time order
// (grabbers write IMU and camera data from different threads; drivers repeat or swap stamps).
//
// Rules, per kind k (IMU, wheel odometry or RGB-D) with window w_k (wheel odometry, a small
// message stream like the IMU's, has the IMU window), and W = max(w_imu, w_rgbd):
//  * a measurement older than the newest one of its kind by more than w_k is dropped (TooLate);
//  * one with a stamp already seen for its kind is dropped (Duplicate);
//  * one older than what was already released is dropped (BehindOutput) — only possible when
//    it is more than W older than the newest measurement of any kind;
//  * otherwise it is kept (Reordered if a newer one of its kind arrived before it).
// A kept measurement is released once it is at least W older than the newest stamp seen, so the
// buffer holds at most W seconds of data and the output is non-decreasing in time across kinds.
// Equal stamps release IMU, then wheel odometry, then RGB-D (the frame's IMU and wheel intervals
// are then complete), then in arrival order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <set>
#include <vector>

#include "rgbdi/io/measurement_source.h"

namespace rgbdi::io {

class TimeOrderingBuffer {
 public:
  enum class Verdict { Accepted, Reordered, Duplicate, TooLate, BehindOutput, InvalidStamp };

  struct Item {
    Measurement m;
    std::size_t record = 0;  ///< where it came from (rawlog record index), for messages
    std::uint64_t seq = 0;   ///< arrival order, the last tie-breaker
  };

  TimeOrderingBuffer(double imu_window_s, double rgbd_window_s);

  /// Offers a measurement; `record` travels with it. Only Accepted/Reordered keep it.
  Verdict push(Measurement m, std::size_t record);
  /// Moves the next releasable measurement into `out`; false when none is releasable yet.
  bool pop(Item& out);
  /// End of input: from now on everything buffered is releasable.
  void finish() { finished_ = true; }

  std::size_t size() const { return heap_.size(); }
  /// Newest stamp of each kind seen so far (NaN before the first one).
  double newestImu() const { return newest_[0]; }
  double newestRgbd() const { return newest_[2]; }
  double newestWheel() const { return newest_[1]; }
  double newest(MeasurementKind k) const { return newest_[static_cast<int>(k)]; }

 private:
  static int kindIndex(const Measurement& m) { return static_cast<int>(kindOf(m)); }
  static bool later(const Item& a, const Item& b);

  double window_[kMeasurementKinds];
  double max_window_;
  double newest_[kMeasurementKinds];
  double newest_any_;
  double released_t_;
  bool any_released_ = false;
  bool finished_ = false;
  std::uint64_t seq_ = 0;
  std::vector<Item> heap_;                       ///< min-heap on (t, kind, seq)
  std::set<double> pending_[kMeasurementKinds];  ///< stamps buffered per kind (duplicates)
  double last_released_[kMeasurementKinds];      ///< newest released stamp per kind (duplicates)
};

}  // namespace rgbdi::io
