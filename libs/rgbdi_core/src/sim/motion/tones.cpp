#include "sim/motion/tones.h"

#include <random>
#include <stdexcept>

namespace rgbdi::sim {

ToneSum bandTones(double derivative_rms, int derivative_order, double f_min, double f_max,
                  int count, double slot_offset, std::uint64_t phase_seed) {
  if (count <= 0 || !(f_min > 0.0) || !(f_max >= f_min) ||
      !(slot_offset > 0.0 && slot_offset < 1.0))
    throw std::invalid_argument(
        "bandTones: need count > 0, 0 < f_min <= f_max, slot_offset in (0, 1)");
  std::vector<Tone> tones;
  if (derivative_rms <= 0.0) return ToneSum(tones);
  // A sinusoid of amplitude a has RMS a / sqrt(2); count of them with distinct frequencies add
  // in power.
  const double derivative_amplitude = derivative_rms * std::sqrt(2.0 / count);
  std::mt19937_64 rng(phase_seed);
  for (int k = 0; k < count; ++k) {
    Tone tone;
    tone.freq_hz = f_min + (f_max - f_min) * (k + slot_offset) / count;
    const double w = 2.0 * M_PI * tone.freq_hz;
    tone.amplitude = derivative_amplitude / std::pow(w, derivative_order);
    // 53 random bits -> [0, 2 pi): the same on every platform (unlike std distributions).
    tone.phase_rad = 2.0 * M_PI * static_cast<double>(rng() >> 11) * 0x1.0p-53;
    tones.push_back(tone);
  }
  return ToneSum(std::move(tones));
}

}  // namespace rgbdi::sim
