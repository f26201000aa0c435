// Percentiles of a latency stream in bounded memory: a fixed-width histogram (one counter per
// bin) plus the exact maximum. Percentiles are reported as the upper edge of the bin holding
// them, so they are exact to one bin width and never under-estimate.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rgbdi::live {

struct LatencySummary {
  std::size_t count = 0;
  double p50_s = 0.0;  ///< [s]
  double p95_s = 0.0;  ///< [s]
  double max_s = 0.0;  ///< [s] exact
};

class LatencyHistogram {
 public:
  /// `bin_s` [s] bin width, `range_s` [s] upper end of the binned range (later values fall into
  /// the last bin; negative values into the first). Throws std::invalid_argument if not > 0.
  LatencyHistogram(double bin_s, double range_s);

  void add(double latency_s);
  /// Upper edge of the bin holding the q-quantile (q in [0, 1]), clamped to the maximum seen.
  double quantile(double q) const;
  LatencySummary summary() const;
  std::size_t count() const { return count_; }

 private:
  double bin_s_;
  std::vector<std::uint32_t> bins_;
  std::size_t count_ = 0;
  double max_ = 0.0;
};

}  // namespace rgbdi::live
