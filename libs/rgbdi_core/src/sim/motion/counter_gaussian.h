// Counter-based random numbers: the n-th number of a stream is a pure function of
// (seed, stream, n). The simulator can therefore draw the noise of any IMU sample or frame in
// any order (or in parallel) and still produce byte-identical output, on every platform
// (std::normal_distribution is implementation-defined).
#pragma once

#include <cmath>
#include <cstdint>

namespace rgbdi::sim {

/// SplitMix64 finaliser: a bijective 64-bit mix with good avalanche.
inline std::uint64_t splitMix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class CounterRng {
 public:
  CounterRng(std::uint64_t seed, std::uint64_t stream)
      : base_(splitMix64(seed + 0x9e3779b97f4a7c15ULL * (stream + 1))) {}

  /// 64 random bits number `index` of the stream (SplitMix64 sequence).
  std::uint64_t bits(std::uint64_t index) const {
    return splitMix64(base_ + 0x9e3779b97f4a7c15ULL * (index + 1));
  }
  /// Uniform in the open interval (0, 1).
  double uniform(std::uint64_t index) const {
    return (static_cast<double>(bits(index) >> 11) + 0.5) * 0x1.0p-53;
  }
  /// Uniform in [-a, a].
  double symmetric(std::uint64_t index, double a) const { return a * (2.0 * uniform(index) - 1.0); }
  /// Standard normal number `index` (Box-Muller on uniforms 2 index and 2 index + 1).
  double gaussian(std::uint64_t index) const {
    const double u1 = uniform(2 * index), u2 = uniform(2 * index + 1);
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }

 private:
  std::uint64_t base_;
};

}  // namespace rgbdi::sim
