#include "rgbdi/loop/hamming_matcher.h"

#include <cstring>
#include <limits>

#include "common/cpu_dispatch.h"

// The x86-64 baseline has no POPCNT instruction; without it GCC expands popcount into ~12
// shift/mask operations. The scan is compiled twice, and the POPCNT copy is used when the CPU
// has it (both give the same numbers).

namespace rgbdi::loop {
namespace {

/// Nearest and second-nearest train descriptor of every query descriptor, and the nearest query
/// of every train descriptor (strict comparisons: ties keep the lower index).
struct Scan {
  std::vector<int> query_best, query_best_dist, query_second_dist;
  std::vector<int> train_best_query, train_best_dist;
};

inline __attribute__((always_inline)) int distanceInline(const std::uint8_t* a,
                                                         const std::uint8_t* b,
                                                         std::uint32_t bytes) {
  int d = 0;
  std::uint32_t i = 0;
  for (; i + 8 <= bytes; i += 8) {  // memcpy: descriptors need not be aligned
    std::uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  for (; i < bytes; ++i) d += __builtin_popcount(static_cast<unsigned>(a[i] ^ b[i]));
  return d;
}

inline __attribute__((always_inline)) void scanInline(const std::uint8_t* query, int n_query,
                                                      const std::uint8_t* train, int n_train,
                                                      std::uint32_t bytes, Scan& s) {
  const int no_second = static_cast<int>(8 * bytes);
  for (int q = 0; q < n_query; ++q) {
    const std::uint8_t* dq = query + static_cast<std::size_t>(q) * bytes;
    int best = std::numeric_limits<int>::max(), second = no_second, best_t = -1;
    for (int t = 0; t < n_train; ++t) {
      const int d = distanceInline(dq, train + static_cast<std::size_t>(t) * bytes, bytes);
      if (d < best) {
        second = best;
        best = d;
        best_t = t;
      } else if (d < second) {
        second = d;
      }
      if (d < s.train_best_dist[t]) {
        s.train_best_dist[t] = d;
        s.train_best_query[t] = q;
      }
    }
    s.query_best[q] = best_t;
    s.query_best_dist[q] = best;
    s.query_second_dist[q] = second > no_second ? no_second : second;
  }
}

void scanPortable(const std::uint8_t* query, int n_query, const std::uint8_t* train, int n_train,
                  std::uint32_t bytes, Scan& s) {
  scanInline(query, n_query, train, n_train, bytes, s);
}

#ifdef RGBDI_HAVE_X86_DISPATCH
__attribute__((target("popcnt"))) void scanPopcnt(const std::uint8_t* query, int n_query,
                                                  const std::uint8_t* train, int n_train,
                                                  std::uint32_t bytes, Scan& s) {
  scanInline(query, n_query, train, n_train, bytes, s);
}
#endif

}  // namespace

int hammingDistance(const std::uint8_t* a, const std::uint8_t* b, std::uint32_t bytes) {
  return distanceInline(a, b, bytes);
}

std::vector<DescriptorMatch> matchDescriptors(const std::uint8_t* query, int n_query,
                                              const std::uint8_t* train, int n_train,
                                              std::uint32_t bytes,
                                              const HammingMatchOptions& options) {
  std::vector<DescriptorMatch> matches;
  if (n_query <= 0 || n_train <= 0 || bytes == 0) return matches;
  Scan s;
  s.query_best.assign(n_query, -1);
  s.query_best_dist.assign(n_query, 0);
  s.query_second_dist.assign(n_query, 0);
  s.train_best_query.assign(n_train, -1);
  s.train_best_dist.assign(n_train, std::numeric_limits<int>::max());
#ifdef RGBDI_HAVE_X86_DISPATCH
  if (__builtin_cpu_supports("popcnt"))
    scanPopcnt(query, n_query, train, n_train, bytes, s);
  else
    scanPortable(query, n_query, train, n_train, bytes, s);
#else
  scanPortable(query, n_query, train, n_train, bytes, s);
#endif
  for (int q = 0; q < n_query; ++q) {
    const int t = s.query_best[q];
    const int d = s.query_best_dist[q];
    if (t < 0 || d > options.max_distance_bits) continue;
    if (!(d < options.ratio * s.query_second_dist[q])) continue;
    if (options.cross_check && s.train_best_query[t] != q) continue;
    matches.push_back({q, t, d});
  }
  return matches;
}

}  // namespace rgbdi::loop
