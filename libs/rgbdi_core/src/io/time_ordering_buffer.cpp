#include "rgbdi/io/time_ordering_buffer.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbdi::io {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

TimeOrderingBuffer::TimeOrderingBuffer(double imu_window_s, double rgbd_window_s)
    : window_{imu_window_s, imu_window_s, rgbd_window_s},
      max_window_(std::max(imu_window_s, rgbd_window_s)),
      newest_{kNaN, kNaN, kNaN},
      newest_any_(kNaN),
      released_t_(kNaN),
      last_released_{kNaN, kNaN, kNaN} {}

bool TimeOrderingBuffer::later(const Item& a, const Item& b) {
  const double ta = measurementTime(a.m), tb = measurementTime(b.m);
  if (ta != tb) return ta > tb;
  const int ka = kindIndex(a.m), kb = kindIndex(b.m);
  if (ka != kb) return ka > kb;
  return a.seq > b.seq;
}

TimeOrderingBuffer::Verdict TimeOrderingBuffer::push(Measurement m, std::size_t record) {
  const double t = measurementTime(m);
  const int k = kindIndex(m);
  if (!std::isfinite(t) || t <= 0.0) return Verdict::InvalidStamp;
  if (t == last_released_[k] || pending_[k].count(t)) return Verdict::Duplicate;
  // NaN comparisons are false: nothing is late before the first measurement of its kind.
  if (t < newest_[k] - window_[k]) return Verdict::TooLate;
  if (any_released_ && t < released_t_) return Verdict::BehindOutput;

  const bool reordered = t < newest_[k];
  if (!(t <= newest_[k])) newest_[k] = t;
  if (!(t <= newest_any_)) newest_any_ = t;
  pending_[k].insert(t);
  heap_.push_back(Item{std::move(m), record, seq_++});
  std::push_heap(heap_.begin(), heap_.end(), later);
  return reordered ? Verdict::Reordered : Verdict::Accepted;
}

bool TimeOrderingBuffer::pop(Item& out) {
  if (heap_.empty()) return false;
  const double t = measurementTime(heap_.front().m);
  if (!finished_ && t > newest_any_ - max_window_) return false;
  std::pop_heap(heap_.begin(), heap_.end(), later);
  out = std::move(heap_.back());
  heap_.pop_back();
  const int k = kindIndex(out.m);
  pending_[k].erase(t);
  last_released_[k] = t;
  released_t_ = t;
  any_released_ = true;
  return true;
}

}  // namespace rgbdi::io
