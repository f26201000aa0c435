#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/texture.h"

namespace rgbdi::sim {
namespace {

std::uint32_t pack(int r, int g, int b) {
  return static_cast<std::uint32_t>(r) | static_cast<std::uint32_t>(g) << 8 |
         static_cast<std::uint32_t>(b) << 16;
}
int channel(std::uint32_t t, int c) { return static_cast<int>((t >> (8 * c)) & 0xffu); }

}  // namespace

MipTexture::MipTexture(const cv::Mat& level0) {
  if (level0.type() != CV_8UC3 || level0.rows != level0.cols || level0.rows < 2 ||
      (level0.rows & (level0.rows - 1)) != 0)
    throw std::invalid_argument("MipTexture: need a square CV_8UC3 image with power-of-two size");
  size0_ = level0.rows;
  period_ = size0_;
  inv_period_ = 1.0 / period_;  // a power of two: wrapping by multiplication is exact
  Level l0;
  l0.size = size0_;
  l0.mask = size0_ - 1;
  l0.texels.resize(static_cast<std::size_t>(size0_) * static_cast<std::size_t>(size0_));
  for (int r = 0; r < size0_; ++r) {
    const std::uint8_t* src = level0.ptr<std::uint8_t>(r);
    for (int c = 0; c < size0_; ++c)
      l0.texels[static_cast<std::size_t>(r) * static_cast<std::size_t>(size0_) +
                static_cast<std::size_t>(c)] = pack(src[3 * c], src[3 * c + 1], src[3 * c + 2]);
  }
  levels_.push_back(std::move(l0));
  // 2x2 box averages: with power-of-two sizes the blocks never straddle the wrap-around seam,
  // so every level stays periodic like the texture itself.
  while (levels_.back().size > 1) {
    const Level& prev = levels_.back();
    Level next;
    next.size = prev.size / 2;
    next.mask = next.size - 1;
    const std::size_t ps = static_cast<std::size_t>(prev.size),
                      ns = static_cast<std::size_t>(next.size);
    next.texels.resize(ns * ns);
    for (std::size_t r = 0; r < ns; ++r)
      for (std::size_t c = 0; c < ns; ++c) {
        const std::uint32_t a = prev.texels[2 * r * ps + 2 * c],
                            b = prev.texels[2 * r * ps + 2 * c + 1];
        const std::uint32_t d = prev.texels[(2 * r + 1) * ps + 2 * c],
                            e = prev.texels[(2 * r + 1) * ps + 2 * c + 1];
        int avg[3];
        for (int k = 0; k < 3; ++k)
          avg[k] = (channel(a, k) + channel(b, k) + channel(d, k) + channel(e, k) + 2) / 4;
        next.texels[r * ns + c] = pack(avg[0], avg[1], avg[2]);
      }
    levels_.push_back(std::move(next));
  }
  for (std::size_t l = 0; l < levels_.size(); ++l)
    scale_.push_back(std::ldexp(1.0f, -static_cast<int>(l)));
}

}  // namespace rgbdi::sim
