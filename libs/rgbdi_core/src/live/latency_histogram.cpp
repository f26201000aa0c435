#include "rgbdi/live/latency_histogram.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rgbdi::live {

LatencyHistogram::LatencyHistogram(double bin_s, double range_s) : bin_s_(bin_s) {
  if (!(bin_s > 0.0) || !(range_s > bin_s))
    throw std::invalid_argument("LatencyHistogram: need 0 < bin_s < range_s");
  bins_.assign(static_cast<std::size_t>(std::ceil(range_s / bin_s)), 0);
}

void LatencyHistogram::add(double latency_s) {
  if (!std::isfinite(latency_s)) return;
  const double x = std::max(0.0, latency_s);
  const auto i = std::min(bins_.size() - 1, static_cast<std::size_t>(x / bin_s_));
  ++bins_[i];
  max_ = count_ == 0 ? latency_s : std::max(max_, latency_s);
  ++count_;
}

double LatencyHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  q = std::clamp(q, 0.0, 1.0);
  // Smallest bin whose cumulative count reaches ceil(q * n) (at least the first sample).
  const auto need = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(q * count_)));
  std::size_t cum = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    cum += bins_[i];
    if (cum >= need) return std::min(max_, (i + 1) * bin_s_);
  }
  return max_;
}

LatencySummary LatencyHistogram::summary() const {
  LatencySummary s;
  s.count = count_;
  s.p50_s = quantile(0.5);
  s.p95_s = quantile(0.95);
  s.max_s = count_ ? max_ : 0.0;
  return s;
}

}  // namespace rgbdi::live
