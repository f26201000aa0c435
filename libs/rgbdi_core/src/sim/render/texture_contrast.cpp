#include <array>
#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/texture.h"

namespace rgbdi::sim {

void scaleTextureContrast(cv::Mat& texture, double contrast) {
  if (texture.type() != CV_8UC3 || texture.empty())
    throw std::invalid_argument("scaleTextureContrast: texture must be a non-empty CV_8UC3 image");
  if (!(contrast > 0.0 && contrast <= 1.0))
    throw std::invalid_argument("scaleTextureContrast: contrast must be in (0, 1]");
  const cv::Scalar mean = cv::mean(texture);
  // A lookup table per channel: 256 entries instead of a multiply per texel.
  std::array<std::array<std::uint8_t, 256>, 3> lut{};
  for (int c = 0; c < 3; ++c)
    for (int v = 0; v < 256; ++v)
      lut[c][v] = cv::saturate_cast<std::uint8_t>(
          static_cast<int>(std::lround(mean[c] + contrast * (static_cast<double>(v) - mean[c]))));
  for (int y = 0; y < texture.rows; ++y) {
    std::uint8_t* p = texture.ptr<std::uint8_t>(y);
    for (int x = 0; x < texture.cols; ++x, p += 3)
      for (int c = 0; c < 3; ++c) p[c] = lut[c][p[c]];
  }
}

}  // namespace rgbdi::sim
