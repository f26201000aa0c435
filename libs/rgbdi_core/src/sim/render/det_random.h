// Platform-independent random numbers for the simulator's procedural content.
//
// std::uniform_*_distribution and std::normal_distribution are implementation-defined, so the
// same seed would give different textures with another standard library; these helpers derive
// every number from the raw std::mt19937_64 output only.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace rgbdi::sim::detail {

/// SplitMix64 finaliser: decorrelates nearby seeds (seed, seed + 1, ...).
inline std::uint64_t mixSeed(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}
inline std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b) { return mixSeed(mixSeed(a) ^ b); }

class DetRandom {
 public:
  explicit DetRandom(std::uint64_t seed) : eng_(mixSeed(seed)) {}
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(eng_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [lo, hi] (inclusive).
  int integer(int lo, int hi) {
    const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;
    return lo + static_cast<int>(eng_() % span);
  }
  bool chance(double p) { return uniform() < p; }
  /// Standard normal (Box-Muller).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  }
  std::uint64_t next() { return eng_(); }

 private:
  std::mt19937_64 eng_;
};

}  // namespace rgbdi::sim::detail
