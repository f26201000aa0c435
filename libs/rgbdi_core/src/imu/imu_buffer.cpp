#include "rgbdi/imu/imu_buffer.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rgbdi::imu {
namespace {

std::string spanText(double t0, double t1) {
  std::ostringstream os;
  os.precision(9);
  os << std::fixed << "[" << t0 << ", " << t1 << "] s";
  return os.str();
}

bool stampBefore(const ImuSample& s, double t) { return s.t < t; }
bool stampAfter(double t, const ImuSample& s) { return t < s.t; }

}  // namespace

void ImuBuffer::push(const ImuSample& sample) {
  if (!std::isfinite(sample.t) || !sample.acc.allFinite() || !sample.gyr.allFinite()) {
    std::ostringstream os;
    os.precision(9);
    os << std::fixed << "ImuBuffer::push: IMU sample at t=" << sample.t
       << " s has a non-finite value";
    throw std::invalid_argument(os.str());
  }
  if (!samples_.empty() && !(sample.t > samples_.back().t)) {
    std::ostringstream os;
    os.precision(9);
    os << std::fixed << "ImuBuffer::push: IMU sample at t=" << sample.t
       << " s is not after the newest buffered sample at t=" << samples_.back().t << " s";
    throw std::invalid_argument(os.str());
  }
  samples_.push_back(sample);
}

double ImuBuffer::oldestTime() const {
  if (samples_.empty()) throw std::logic_error("ImuBuffer::oldestTime: buffer is empty");
  return samples_.front().t;
}

double ImuBuffer::newestTime() const {
  if (samples_.empty()) throw std::logic_error("ImuBuffer::newestTime: buffer is empty");
  return samples_.back().t;
}

bool ImuBuffer::covers(double t0, double t1) const {
  return !samples_.empty() && t0 <= t1 && samples_.front().t <= t0 && samples_.back().t >= t1;
}

ImuSample ImuBuffer::interpolate(double t) const {
  if (!covers(t, t)) {
    throw std::out_of_range("ImuBuffer::interpolate: t=" + spanText(t, t) +
                            " is outside the buffered IMU span " +
                            (samples_.empty() ? std::string("(empty)")
                                              : spanText(samples_.front().t, samples_.back().t)));
  }
  // First sample at or after t; it exists because t <= newest stamp.
  const auto hi = std::lower_bound(samples_.begin(), samples_.end(), t, stampBefore);
  if (hi->t == t || hi == samples_.begin()) return *hi;
  const auto lo = std::prev(hi);
  const double w = (t - lo->t) / (hi->t - lo->t);
  ImuSample s;
  s.t = t;
  s.acc = (1.0 - w) * lo->acc + w * hi->acc;
  s.gyr = (1.0 - w) * lo->gyr + w * hi->gyr;
  return s;
}

std::vector<ImuSample> ImuBuffer::between(double t0, double t1) const {
  if (!(t1 > t0))
    throw std::invalid_argument("ImuBuffer::between: empty interval " + spanText(t0, t1));
  if (!covers(t0, t1)) {
    throw std::out_of_range("ImuBuffer::between: requested " + spanText(t0, t1) +
                            " is not covered by the buffered IMU span " +
                            (samples_.empty() ? std::string("(empty)")
                                              : spanText(samples_.front().t, samples_.back().t)));
  }
  std::vector<ImuSample> out;
  out.push_back(interpolate(t0));
  const auto first_inside = std::upper_bound(samples_.begin(), samples_.end(), t0, stampAfter);
  const auto end_inside = std::lower_bound(first_inside, samples_.end(), t1, stampBefore);
  out.insert(out.end(), first_inside, end_inside);
  out.push_back(interpolate(t1));
  return out;
}

std::size_t ImuBuffer::popOlderThan(double t) {
  // Samples strictly after t are all kept; of those at or before t only the newest is kept.
  const auto first_after = std::upper_bound(samples_.begin(), samples_.end(), t, stampAfter);
  if (first_after == samples_.begin()) return 0;
  const std::size_t drop = static_cast<std::size_t>(first_after - samples_.begin()) - 1;
  samples_.erase(samples_.begin(), samples_.begin() + static_cast<std::ptrdiff_t>(drop));
  return drop;
}

}  // namespace rgbdi::imu
