#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/texture.h"

namespace rgbdi::sim {

MipTexture::MipTexture(const cv::Mat& level0) {
  if (level0.type() != CV_8UC3 || level0.rows != level0.cols || level0.rows < 2 ||
      (level0.rows & (level0.rows - 1)) != 0)
    throw std::invalid_argument("MipTexture: need a square CV_8UC3 image with power-of-two size");
  size0_ = level0.rows;
  Level l0;
  l0.size = size0_;
  l0.mask = size0_ - 1;
  l0.rgb.resize(static_cast<std::size_t>(size0_) * size0_ * 3);
  for (int r = 0; r < size0_; ++r) {
    const std::uint8_t* src = level0.ptr<std::uint8_t>(r);
    std::copy(src, src + size0_ * 3, l0.rgb.begin() + static_cast<std::ptrdiff_t>(r) * size0_ * 3);
  }
  levels_.push_back(std::move(l0));
  // 2x2 box averages: with power-of-two sizes the blocks never straddle the wrap-around seam,
  // so every level stays periodic like the texture itself.
  while (levels_.back().size > 1) {
    const Level& prev = levels_.back();
    Level next;
    next.size = prev.size / 2;
    next.mask = next.size - 1;
    next.rgb.resize(static_cast<std::size_t>(next.size) * next.size * 3);
    const std::size_t ps = static_cast<std::size_t>(prev.size);
    for (int r = 0; r < next.size; ++r)
      for (int c = 0; c < next.size; ++c)
        for (int ch = 0; ch < 3; ++ch) {
          const std::size_t r0 = static_cast<std::size_t>(2 * r), c0 = static_cast<std::size_t>(2 * c);
          const std::size_t k = static_cast<std::size_t>(ch);
          const int sum = prev.rgb[(r0 * ps + c0) * 3 + k] + prev.rgb[(r0 * ps + c0 + 1) * 3 + k] +
                          prev.rgb[((r0 + 1) * ps + c0) * 3 + k] +
                          prev.rgb[((r0 + 1) * ps + c0 + 1) * 3 + k];
          next.rgb[(static_cast<std::size_t>(r) * static_cast<std::size_t>(next.size) +
                    static_cast<std::size_t>(c)) * 3 + k] = static_cast<std::uint8_t>((sum + 2) / 4);
        }
    levels_.push_back(std::move(next));
  }
  for (std::size_t l = 0; l < levels_.size(); ++l)
    scale_.push_back(std::ldexp(1.0f, -static_cast<int>(l)));
}

namespace {

// floor() for the texel coordinate range (|x| < 2^31) without a libm call.
inline int floorToInt(float x) {
  const int i = static_cast<int>(x);
  return (static_cast<float>(i) > x) ? i - 1 : i;
}

}  // namespace

Eigen::Vector3f MipTexture::bilinear(const Level& lv, float u, float v) const {
  const float x = u - 0.5f, y = v - 0.5f;
  const int xi = floorToInt(x), yi = floorToInt(y);
  const float ax = x - static_cast<float>(xi), ay = y - static_cast<float>(yi);
  const std::size_t s = static_cast<std::size_t>(lv.size);
  const std::size_t x0 = static_cast<std::size_t>(xi & lv.mask) * 3;
  const std::size_t x1 = static_cast<std::size_t>((xi + 1) & lv.mask) * 3;
  const std::size_t r0 = static_cast<std::size_t>(yi & lv.mask) * s * 3;
  const std::size_t r1 = static_cast<std::size_t>((yi + 1) & lv.mask) * s * 3;
  const std::uint8_t* p00 = &lv.rgb[r0 + x0];
  const std::uint8_t* p01 = &lv.rgb[r0 + x1];
  const std::uint8_t* p10 = &lv.rgb[r1 + x0];
  const std::uint8_t* p11 = &lv.rgb[r1 + x1];
  const float w00 = (1 - ax) * (1 - ay), w01 = ax * (1 - ay), w10 = (1 - ax) * ay, w11 = ax * ay;
  return {w00 * p00[0] + w01 * p01[0] + w10 * p10[0] + w11 * p11[0],
          w00 * p00[1] + w01 * p01[1] + w10 * p10[1] + w11 * p11[1],
          w00 * p00[2] + w01 * p01[2] + w10 * p10[2] + w11 * p11[2]};
}

Eigen::Vector3f MipTexture::sample(double u, double v, float lod) const {
  // Wrap to one period first so float keeps sub-texel precision whatever the offsets.
  // (1/period is a power of two, so the product is exact.)
  const double period = static_cast<double>(size0_), inv_period = 1.0 / period;
  const float uf = static_cast<float>(u - period * std::floor(u * inv_period));
  const float vf = static_cast<float>(v - period * std::floor(v * inv_period));
  const int top = levels() - 1;
  if (!(lod > 0.0f)) return bilinear(levels_[0], uf, vf);  // also catches NaN
  if (lod >= static_cast<float>(top)) {
    const float s = scale_[static_cast<std::size_t>(top)];
    return bilinear(levels_[static_cast<std::size_t>(top)], uf * s, vf * s);
  }
  const int l = static_cast<int>(lod);
  const float f = lod - static_cast<float>(l);
  const float s0 = scale_[static_cast<std::size_t>(l)], s1 = 0.5f * s0;
  const Eigen::Vector3f c0 = bilinear(levels_[static_cast<std::size_t>(l)], uf * s0, vf * s0);
  const Eigen::Vector3f c1 = bilinear(levels_[static_cast<std::size_t>(l + 1)], uf * s1, vf * s1);
  return c0 + f * (c1 - c0);
}

}  // namespace rgbdi::sim
