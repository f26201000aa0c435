#include "rgbdi/frontend/depth_sampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace rgbdi::frontend {

double sampleDepth(const cv::Mat& depth_m, const Eigen::Vector2d& uv,
                   const FrontendOptions& options) {
  if (depth_m.type() != CV_32FC1)
    throw std::invalid_argument("sampleDepth: depth image must be CV_32FC1 metres, got type " +
                                std::to_string(depth_m.type()));
  // Also keeps the integer conversions below in range for wild inputs.
  if (!(uv.x() >= 0.0 && uv.y() >= 0.0 && uv.x() <= depth_m.cols - 1 && uv.y() <= depth_m.rows - 1))
    return 0.0;

  const int n = options.depth_neighbourhood_px;
  // Bilinear support: the pixel at or left/above uv and its right/lower neighbours.
  const int u0 = static_cast<int>(std::floor(uv.x()));
  const int v0 = static_cast<int>(std::floor(uv.y()));
  const int uc = static_cast<int>(std::lround(uv.x()));
  const int vc = static_cast<int>(std::lround(uv.y()));
  const bool bilinear = n > 0;
  // The checked window covers both the neighbourhood of the nearest pixel and the interpolation
  // support, so no pixel that contributes to the value escapes the hole/edge test.
  const int umin = std::min(uc - n, u0), vmin = std::min(vc - n, v0);
  const int umax = bilinear ? std::max(uc + n, u0 + 1) : uc;
  const int vmax = bilinear ? std::max(vc + n, v0 + 1) : vc;
  if (umin < 0 || vmin < 0 || umax >= depth_m.cols || vmax >= depth_m.rows) return 0.0;

  // Called for every feature of every image: the window's values go to a buffer kept by the
  // thread (depth_neighbourhood_px is at most 20: 42 x 42 values), not a fresh allocation.
  thread_local std::vector<float> window;
  window.clear();
  float lo = 0.0f, hi = 0.0f;
  for (int v = vmin; v <= vmax; ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = umin; u <= umax; ++u) {
      const float d = row[u];
      if (!(d > 0.0f) || !std::isfinite(d)) return 0.0;  // hole (or garbage) in the window
      if (window.empty() || d < lo) lo = d;
      if (window.empty() || d > hi) hi = d;
      window.push_back(d);
    }
  }
  const size_t mid = window.size() / 2;
  std::nth_element(window.begin(), window.begin() + static_cast<std::ptrdiff_t>(mid), window.end());
  const double median = window[mid];
  // A depth edge is a spread larger than both the relative tolerance and what sensor noise
  // (sigma = coeff z^2) produces in a window of this size.
  const double noise_spread =
      options.depth_max_noise_sigmas * options.depth_noise_coeff * median * median;
  if ((hi - lo) > std::max(options.depth_max_relative_spread * median, noise_spread)) return 0.0;

  double z;
  if (bilinear) {
    const double a = uv.x() - u0, b = uv.y() - v0;
    const double d00 = depth_m.at<float>(v0, u0), d10 = depth_m.at<float>(v0, u0 + 1);
    const double d01 = depth_m.at<float>(v0 + 1, u0), d11 = depth_m.at<float>(v0 + 1, u0 + 1);
    z = (1 - b) * ((1 - a) * d00 + a * d10) + b * ((1 - a) * d01 + a * d11);
  } else {
    z = depth_m.at<float>(vc, uc);
  }
  if (z < options.depth_min_m || z > options.depth_max_m) return 0.0;
  return z;
}

}  // namespace rgbdi::frontend
