#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/exposure.h"
#include "sim/motion/counter_gaussian.h"

namespace rgbdi::sim {
namespace {

// Random stream of the knot values (the IMU uses streams 1-3, the frame noise 100).
constexpr std::uint64_t kExposureStream = 200;
constexpr double kMaxAmplitude = 0.9;  // the gain stays >= 0.1

}  // namespace

ExposureOptions ExposureOptions::load(IniReader& ini) {
  ExposureOptions o;
  const std::string s = "sim";
  o.gain_amplitude =
      ini.getDouble(s, "exposure_gain_amplitude", o.gain_amplitude, 0.0, kMaxAmplitude);
  o.period_s = ini.getDouble(s, "exposure_period_s", o.period_s, 0.0, 1.0e6);
  if (!(o.period_s > 0.0)) ini.fail(s, "exposure_period_s", "must be greater than 0");
  return o;
}

ExposureGain::ExposureGain(const ExposureOptions& options, std::uint64_t seed)
    : options_(options), seed_(seed) {
  if (!(options.gain_amplitude >= 0.0 && options.gain_amplitude <= kMaxAmplitude))
    throw std::invalid_argument("ExposureOptions: gain_amplitude must be in [0, 0.9]");
  if (!(options.period_s > 0.0) || !std::isfinite(options.period_s))
    throw std::invalid_argument("ExposureOptions: period_s must be positive");
}

double ExposureGain::knot(std::uint64_t k) const {
  return CounterRng(seed_, kExposureStream).symmetric(k, 1.0);
}

double ExposureGain::gain(double t) const {
  if (constant()) return 1.0;
  const double spacing = 0.25 * options_.period_s;  // see the model in exposure.h
  const double x = std::max(0.0, t) / spacing;
  const double k = std::floor(x), f = x - k;
  // Degree-5 smooth step: a convex blend of two knots, so p stays within [-1, 1].
  const double w = f * f * f * (f * (6.0 * f - 15.0) + 10.0);
  const auto i = static_cast<std::uint64_t>(k);
  const double p = (1.0 - w) * knot(i) + w * knot(i + 1);
  return 1.0 + options_.gain_amplitude * p;
}

void applyExposureGain(cv::Mat& rgb, double gain) {
  if (rgb.type() != CV_8UC3 || rgb.empty())
    throw std::invalid_argument("applyExposureGain: image must be a non-empty CV_8UC3 image");
  if (!(gain >= 0.0) || !std::isfinite(gain))
    throw std::invalid_argument("applyExposureGain: gain must be finite and >= 0");
  rgb.convertTo(rgb, CV_8UC3, gain);  // rounds and saturates at 0 and 255
}

}  // namespace rgbdi::sim
