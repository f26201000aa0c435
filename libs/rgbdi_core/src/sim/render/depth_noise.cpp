#include <cmath>
#include <limits>
#include <stdexcept>

#include "rgbdi/sim/sensor_noise.h"
#include "sim/render/det_random.h"

namespace rgbdi::sim {

DepthNoiseOptions DepthNoiseOptions::load(IniReader& ini) {
  DepthNoiseOptions o;
  const std::string s = "sim";
  o.sigma_coeff = ini.getDouble(s, "depth_sigma_coeff", o.sigma_coeff, 0.0, 0.1);
  o.min_m = ini.getDouble(s, "depth_min_m", o.min_m, 0.0, 10.0);
  o.max_m = ini.getDouble(s, "depth_max_m", o.max_m, 0.1, 65.0);
  if (o.max_m <= o.min_m)
    ini.fail(s, "depth_max_m",
             "must be greater than depth_min_m (" + std::to_string(o.min_m) + ")");
  o.hole_fraction = ini.getDouble(s, "depth_hole_fraction", o.hole_fraction, 0.0, 0.5);
  return o;
}

namespace {

void validate(const DepthNoiseOptions& o) {
  if (!(o.sigma_coeff >= 0.0) || !(o.min_m >= 0.0) || !(o.max_m > o.min_m) || o.max_m > 65.0)
    throw std::invalid_argument(
        "DepthNoiseOptions: need sigma_coeff >= 0 and 0 <= min_m < max_m <= 65 m");
  if (!(o.hole_fraction >= 0.0 && o.hole_fraction <= 0.5))
    throw std::invalid_argument("DepthNoiseOptions: hole_fraction must be in [0, 0.5]");
  if (!(o.hole_radius_min_px >= 0.5) || !(o.hole_radius_max_px >= o.hole_radius_min_px) ||
      o.hole_radius_max_px > 100.0)
    throw std::invalid_argument(
        "DepthNoiseOptions: need 0.5 <= hole_radius_min_px <= hole_radius_max_px <= 100");
}

}  // namespace

cv::Mat makeDepthHoleMask(cv::Size size, const DepthNoiseOptions& options, std::mt19937_64& rng) {
  validate(options);
  if (size.width <= 0 || size.height <= 0)
    throw std::invalid_argument("makeDepthHoleMask: empty image size");
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  const long long total = static_cast<long long>(size.width) * size.height;
  const long long target = std::llround(options.hole_fraction * static_cast<double>(total));
  detail::DetRandom r(rng());
  long long covered = 0;
  // Random ellipses, painted pixel by pixel so painting stops exactly at the target count.
  while (covered < target) {
    const double cx = r.uniform(0, size.width), cy = r.uniform(0, size.height);
    const double a = r.uniform(options.hole_radius_min_px, options.hole_radius_max_px);
    const double b = r.uniform(options.hole_radius_min_px, options.hole_radius_max_px);
    const double ang = r.uniform(0, M_PI), ca = std::cos(ang), sa = std::sin(ang);
    const double ext = std::max(a, b);
    const int x0 = std::max(0, static_cast<int>(std::floor(cx - ext)));
    const int x1 = std::min(size.width - 1, static_cast<int>(std::ceil(cx + ext)));
    const int y0 = std::max(0, static_cast<int>(std::floor(cy - ext)));
    const int y1 = std::min(size.height - 1, static_cast<int>(std::ceil(cy + ext)));
    for (int y = y0; y <= y1 && covered < target; ++y) {
      std::uint8_t* row = mask.ptr<std::uint8_t>(y);
      for (int x = x0; x <= x1 && covered < target; ++x) {
        const double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
        const double p = (ca * dx + sa * dy) / a, q = (-sa * dx + ca * dy) / b;
        if (p * p + q * q <= 1.0 && row[x] == 0) {
          row[x] = 255;
          ++covered;
        }
      }
    }
  }
  return mask;
}

cv::Mat applyDepthNoise(const cv::Mat& ideal_depth_m, const DepthNoiseOptions& options,
                        std::mt19937_64& rng) {
  if (ideal_depth_m.type() != CV_32FC1 || ideal_depth_m.empty())
    throw std::invalid_argument("applyDepthNoise: ideal depth must be a non-empty CV_32FC1 image");
  validate(options);
  cv::Mat gauss(ideal_depth_m.size(), CV_32FC1);
  cv::RNG cvrng(rng());
  cvrng.fill(gauss, cv::RNG::NORMAL, 0.0, 1.0);
  const cv::Mat holes = makeDepthHoleMask(ideal_depth_m.size(), options, rng);
  cv::Mat out(ideal_depth_m.size(), CV_16UC1);
  // Range gate on the measured value, in whole millimetres as the sensor reports it.
  const double min_mm = std::ceil(options.min_m * 1000.0 - 1e-9);
  const double max_mm = std::floor(options.max_m * 1000.0 + 1e-9);
  for (int y = 0; y < out.rows; ++y) {
    const float* z = ideal_depth_m.ptr<float>(y);
    const float* g = gauss.ptr<float>(y);
    const std::uint8_t* h = holes.ptr<std::uint8_t>(y);
    std::uint16_t* o = out.ptr<std::uint16_t>(y);
    for (int x = 0; x < out.cols; ++x) {
      const double zi = z[x];
      o[x] = 0;
      if (h[x] != 0 || !(zi > 0.0) || !std::isfinite(zi)) continue;
      const double mm = std::round((zi + options.sigma_coeff * zi * zi * g[x]) * 1000.0);
      if (mm < min_mm || mm > max_mm) continue;
      o[x] = static_cast<std::uint16_t>(mm);
    }
  }
  return out;
}

}  // namespace rgbdi::sim
