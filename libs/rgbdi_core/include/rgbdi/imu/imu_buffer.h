// Time-ordered IMU samples waiting to be pre-integrated between frames.
#pragma once

#include <cstddef>
#include <deque>
#include <vector>

#include "rgbdi/common/types.h"

namespace rgbdi::imu {

class ImuBuffer {
 public:
  /// Appends a sample. Throws std::invalid_argument when its stamp is not strictly after the
  /// newest buffered sample or a value is not finite (the stream stage reorders; here order is a
  /// precondition).
  void push(const ImuSample& sample);

  bool empty() const { return samples_.empty(); }
  std::size_t size() const { return samples_.size(); }
  const std::deque<ImuSample>& samples() const { return samples_; }
  /// Stamps of the oldest / newest sample; throw std::logic_error when empty.
  double oldestTime() const;
  double newestTime() const;

  /// True when samples exist at or before t0 and at or after t1 (t0 <= t1).
  bool covers(double t0, double t1) const;
  /// Linear interpolation at t; throws std::out_of_range when t is outside the buffered span.
  ImuSample interpolate(double t) const;
  /// Samples covering [t0, t1]: an interpolated sample exactly at t0, every buffered sample
  /// strictly inside (t0, t1), and an interpolated sample exactly at t1 (a buffered sample that
  /// falls exactly on t0 or t1 is used as is). Throws std::invalid_argument when t1 <= t0 and
  /// std::out_of_range (naming the requested and buffered spans) when !covers(t0, t1).
  std::vector<ImuSample> between(double t0, double t1) const;

  /// Drops the samples no interval starting at or after t needs: every sample older than t except
  /// the newest one at or before t (kept to interpolate at t). Returns how many were dropped.
  std::size_t popOlderThan(double t);

 private:
  std::deque<ImuSample> samples_;
};

}  // namespace rgbdi::imu
