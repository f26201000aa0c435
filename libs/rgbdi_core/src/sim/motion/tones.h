// Sums of sinusoids ("tones") used for walking sway, hand motion, track vibration and jitter.
// Being analytic, they differentiate exactly in Taylor arithmetic; distinct frequencies per axis
// keep products of axes (coning / sculling) free of a constant part.
#pragma once

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "rgbdi/sim/motion_taylor.h"

namespace rgbdi::sim {

struct Tone {
  double amplitude = 0.0;  ///< in the unit of the signal
  double freq_hz = 0.0;
  double phase_rad = 0.0;
};

class ToneSum {
 public:
  ToneSum() = default;
  explicit ToneSum(std::vector<Tone> tones) : tones_(std::move(tones)) {}

  template <int K>
  Taylor<K> at(const Taylor<K>& t) const {
    Taylor<K> r;
    for (const Tone& tone : tones_)
      r += tone.amplitude * sin((2.0 * M_PI * tone.freq_hz) * t + tone.phase_rad);
    return r;
  }
  double at(double t) const { return at(Taylor<0>(t)).value(); }
  const std::vector<Tone>& tones() const { return tones_; }
  bool empty() const { return tones_.empty(); }

 private:
  std::vector<Tone> tones_;
};

/// `count` tones with frequencies spread evenly over [f_min, f_max] (slot k at
/// f_min + (f_max - f_min) (k + slot_offset) / count, slot_offset in (0, 1), so different offsets
/// give disjoint frequency sets) and random phases from `phase_seed`. Amplitudes are equal in
/// the `derivative_order`-th time derivative (0: the signal, 1: its rate, 2: its acceleration)
/// and scaled so that derivative has RMS `derivative_rms`.
ToneSum bandTones(double derivative_rms, int derivative_order, double f_min, double f_max,
                  int count, double slot_offset, std::uint64_t phase_seed);

}  // namespace rgbdi::sim
