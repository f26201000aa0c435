#include "rgbdi/loop/hamming_matcher.h"

#include <cstring>
#include <limits>

namespace rgbdi::loop {

int hammingDistance(const std::uint8_t* a, const std::uint8_t* b, std::uint32_t bytes) {
  int d = 0;
  std::uint32_t i = 0;
  // Eight bytes at a time (memcpy: descriptors need not be aligned).
  for (; i + 8 <= bytes; i += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  for (; i < bytes; ++i) d += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return d;
}

std::vector<DescriptorMatch> matchDescriptors(const std::uint8_t* query, int n_query,
                                              const std::uint8_t* train, int n_train,
                                              std::uint32_t bytes,
                                              const HammingMatchOptions& options) {
  std::vector<DescriptorMatch> matches;
  if (n_query <= 0 || n_train <= 0 || bytes == 0) return matches;
  const int no_second = static_cast<int>(8 * bytes);
  // Best query of every train descriptor, for the mutual check.
  std::vector<int> train_best_query(n_train, -1);
  std::vector<int> train_best_dist(n_train, std::numeric_limits<int>::max());
  std::vector<int> query_best(n_query, -1), query_best_dist(n_query, 0),
      query_second_dist(n_query, no_second);
  for (int q = 0; q < n_query; ++q) {
    const std::uint8_t* dq = query + static_cast<std::size_t>(q) * bytes;
    int best = std::numeric_limits<int>::max(), second = no_second, best_t = -1;
    for (int t = 0; t < n_train; ++t) {
      const int d = hammingDistance(dq, train + static_cast<std::size_t>(t) * bytes, bytes);
      if (d < best) {
        second = best;
        best = d;
        best_t = t;
      } else if (d < second) {
        second = d;
      }
      if (d < train_best_dist[t]) {  // strict: ties keep the lower query index
        train_best_dist[t] = d;
        train_best_query[t] = q;
      }
    }
    query_best[q] = best_t;
    query_best_dist[q] = best;
    query_second_dist[q] = second > no_second ? no_second : second;
  }
  for (int q = 0; q < n_query; ++q) {
    const int t = query_best[q];
    const int d = query_best_dist[q];
    if (t < 0 || d > options.max_distance_bits) continue;
    if (!(d < options.ratio * query_second_dist[q])) continue;
    if (options.cross_check && train_best_query[t] != q) continue;
    matches.push_back({q, t, d});
  }
  return matches;
}

}  // namespace rgbdi::loop
