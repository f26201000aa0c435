// Brute-force nearest-neighbour matching of binary descriptors by Hamming distance, with Lowe's
// ratio test and an optional mutual (cross) check. Deterministic: ties go to the lower index.
#pragma once

#include <cstdint>
#include <vector>

namespace rgbdi::loop {

struct DescriptorMatch {
  int query = 0;  ///< index of the query descriptor
  int train = 0;  ///< index of the matched (candidate) descriptor
  int distance_bits = 0;
};

struct HammingMatchOptions {
  double ratio = 0.8;          ///< [unitless] best < ratio * second best (second best must exist)
  int max_distance_bits = 64;  ///< [bits]
  bool cross_check = true;     ///< the train descriptor's nearest query must be this one
};

/// Hamming distance of two descriptors of `bytes` bytes.
int hammingDistance(const std::uint8_t* a, const std::uint8_t* b, std::uint32_t bytes);

/// Matches every query descriptor (n_query x bytes, row-major) against the train set. Result in
/// increasing query index. A train set of one descriptor has no second best: the ratio test then
/// compares against the largest possible distance (8 * bytes).
std::vector<DescriptorMatch> matchDescriptors(const std::uint8_t* query, int n_query,
                                              const std::uint8_t* train, int n_train,
                                              std::uint32_t bytes,
                                              const HammingMatchOptions& options);

}  // namespace rgbdi::loop
