#include <stdexcept>

#include "rgbdi/sim/sensor_noise.h"

namespace rgbdi::sim {

ColorNoiseOptions ColorNoiseOptions::load(IniReader& ini) {
  ColorNoiseOptions o;
  o.sigma = ini.getDouble("sim", "photometric_noise_sigma", o.sigma, 0.0, 50.0);
  return o;
}

void applyColorNoise(cv::Mat& rgb, const ColorNoiseOptions& options, std::mt19937_64& rng) {
  if (rgb.type() != CV_8UC3 || rgb.empty())
    throw std::invalid_argument("applyColorNoise: image must be a non-empty CV_8UC3 image");
  if (!(options.sigma >= 0.0)) throw std::invalid_argument("ColorNoiseOptions: sigma must be >= 0");
  // Draw even when sigma is 0 so the generator advances the same way for any sigma.
  cv::RNG cvrng(rng());
  if (options.sigma == 0.0) return;
  cv::Mat noise(rgb.size(), CV_32FC3);
  cvrng.fill(noise, cv::RNG::NORMAL, 0.0, options.sigma);
  for (int y = 0; y < rgb.rows; ++y) {
    std::uint8_t* p = rgb.ptr<std::uint8_t>(y);
    const float* n = noise.ptr<float>(y);
    for (int x = 0; x < rgb.cols * 3; ++x) p[x] = cv::saturate_cast<std::uint8_t>(p[x] + n[x]);
  }
}

}  // namespace rgbdi::sim
