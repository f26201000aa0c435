// Auto-exposure of the simulated colour camera: the image gain drifts smoothly in time, as a
// camera's auto-exposure follows the scene brightness.
//
// Model: gain(t) = 1 + a p(t), with p a seeded smooth random process in [-1, 1]: values drawn
// uniformly in [-1, 1] at knots every period / 4 seconds, joined by the degree-5 smooth step (C2:
// gain rate and its derivative continuous). p crosses 0 once per knot interval with probability
// 1/2, i.e. on average twice per period, as a sinusoid of that period does. The
// gain multiplies the rendered colour before the sensor noise, clipped to 0..255; depth is not
// affected. Every knot value is a pure function of (seed, knot index).
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::sim {

struct ExposureOptions {
  double gain_amplitude = 0.0;  ///< [unitless] a in [0, 0.9]; 0 = constant gain 1 (off)
  double period_s = 8.0;        ///< [s] typical period of the gain variation (> 0)

  /// Reads [sim] exposure_gain_amplitude, exposure_period_s.
  static ExposureOptions load(IniReader& ini);
};

class ExposureGain {
 public:
  /// Throws std::invalid_argument unless 0 <= gain_amplitude <= 0.9 and period_s > 0.
  ExposureGain(const ExposureOptions& options, std::uint64_t seed);
  /// Gain at time t [s] since the start of the sequence (t >= 0), in [1 - a, 1 + a].
  double gain(double t) const;
  /// Whether the gain is 1 at all times (amplitude 0).
  bool constant() const { return options_.gain_amplitude == 0.0; }

 private:
  double knot(std::uint64_t k) const;  ///< p at knot k, uniform in [-1, 1]

  ExposureOptions options_;
  std::uint64_t seed_;
};

/// Multiplies a CV_8UC3 image by gain in place, rounding and clipping to 0..255.
void applyExposureGain(cv::Mat& rgb, double gain);

}  // namespace rgbdi::sim
