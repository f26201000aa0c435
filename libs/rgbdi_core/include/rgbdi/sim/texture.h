// Procedural, deterministic surface textures with mip maps.
//
// A few large periodic textures (default 1024 texels of 4 mm = 4.1 m period) are generated per
// style from the scene seed; each surface (material) looks at its own part of one of them, with
// its own orientation and colour gain, so neighbouring surfaces differ while memory stays small.
// Patterns are layered shapes with strong contrast at several scales (posters, bricks, tiles,
// shelves, speckled concrete, planks) and random sizes/positions, so there is no short-scale
// periodicity for KLT to alias on. Sampling is trilinear over a box-filtered mip chain chosen
// from the pixel footprint, so distant surfaces blur instead of aliasing into fake corners.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <utility>
#include <string>
#include <vector>

namespace rgbdi::sim {

enum class TextureStyle { Posters, Bricks, Tiles, Shelves, Speckle, Planks };
constexpr int kTextureStyleCount = 6;
std::string toString(TextureStyle style);

struct TextureOptions {
  double texel_size_m = 0.004;  ///< [m] world size of one finest-level texel
  int size_log2 = 10;           ///< textures are 2^size_log2 texels square (period 4.1 m at defaults)
  int variants_per_style = 2;   ///< distinct generated textures per style
};

/// Generates one periodic (seamlessly wrapping) texture: CV_8UC3, R,G,B order, size x size.
/// Same (style, size, texel, seed) -> identical bytes.
cv::Mat generateTexture(TextureStyle style, int size, double texel_size_m, std::uint64_t seed);

/// A square power-of-two RGB texture with its mip chain (each level a 2x2 box average of the
/// previous one, wrapping at the borders like the texture itself).
class MipTexture {
 public:
  /// level0: CV_8UC3, square, power-of-two size >= 2.
  explicit MipTexture(const cv::Mat& level0);
  int levels() const { return static_cast<int>(levels_.size()); }
  int size() const { return size0_; }
  /// Trilinear sample at finest-level texel coordinates (u right, v down; wrapping; texel
  /// centres at integer + 0.5) and level of detail lod (0 = finest; clamped to the chain).
  /// Returns R,G,B in [0, 255].
  Eigen::Vector3f sample(double u, double v, float lod) const;

 private:
  struct Level {
    int size = 0, mask = 0;
    /// size*size texels, row-major, packed R | G << 8 | B << 16 (one load per texel, and the
    /// bilinear filter works on two channels per integer multiply).
    std::vector<std::uint32_t> texels;
  };
  /// Bilinear sample of one level, packed like the texels.
  std::uint32_t bilinear(const Level& lv, float u, float v) const;
  std::vector<Level> levels_;
  std::vector<float> scale_;  ///< texel coordinate scale of each level (2^-level)
  int size0_ = 0;
  double period_ = 0.0, inv_period_ = 0.0;  ///< size of level 0 [texels] and its inverse
};

/// What a surface looks like: a style and its own seed (drives the choice of texture, offset,
/// orientation and colour gain).
struct Material {
  TextureStyle style = TextureStyle::Posters;
  std::uint64_t seed = 0;
};

/// A material resolved onto the texture bank.
struct MaterialAppearance {
  int texture = 0;                              ///< index into TextureBank
  Eigen::Vector2d offset_m = Eigen::Vector2d::Zero();  ///< [m] shift of the surface coordinates
  int orientation = 0;                          ///< 0..7: quarter turns (bits 0-1) and mirror (bit 2)
  Eigen::Vector3f gain = Eigen::Vector3f::Ones();  ///< per-channel colour gain
};

class TextureBank {
 public:
  TextureBank(std::uint64_t seed, const TextureOptions& options);

  const TextureOptions& options() const { return options_; }
  /// Resolves a material, generating the texture it uses on first request (not thread-safe;
  /// Scene::build() resolves all materials before any rendering).
  MaterialAppearance resolve(const Material& material);
  std::size_t textureCount() const { return textures_.size(); }

  /// Colour (R,G,B in [0, 255]) of a surface at texture coordinates uv [m], seen with a pixel
  /// footprint [m] on the surface (selects the mip level).
  Eigen::Vector3f sample(const MaterialAppearance& appearance, const Eigen::Vector2d& uv_m,
                         double footprint_m) const;

 private:
  std::uint64_t seed_;
  TextureOptions options_;
  double inv_texel_;  ///< texels per metre (avoids a division per sample)
  std::vector<MipTexture> textures_;
  std::map<std::pair<int, int>, int> index_;  ///< (style, variant) -> texture
};

// ---- Hot path, inline so that a renderer's pixel loop compiles it in place ----

namespace detail {

// floor() for the texel coordinate range (|x| < 2^31) without a libm call.
inline int floorToInt(float x) {
  const int i = static_cast<int>(x);
  return (static_cast<float>(i) > x) ? i - 1 : i;
}

// x modulo `period` (a power of two) in [0, period), computed in double so large surface
// coordinates keep sub-texel precision before dropping to float.
inline float wrapPeriod(double x, double period, double inv_period) {
  const double q = x * inv_period;
  long long k = static_cast<long long>(q);
  if (static_cast<double>(k) > q) --k;
  return static_cast<float>(x - period * static_cast<double>(k));
}

// log2 from the float's exponent plus a quadratic fit of the mantissa (error < 0.01 levels,
// plenty for choosing a mip level, and several times faster than std::log2).
inline float fastLog2(float x) {
  if (!(x > 0.0f)) return -126.0f;
  std::uint32_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int exponent = static_cast<int>((bits >> 23) & 0xffu) - 127;
  bits = (bits & 0x007fffffu) | 0x3f800000u;  // mantissa as a float in [1, 2)
  float m;
  std::memcpy(&m, &bits, sizeof m);
  const float t = m - 1.0f;
  return static_cast<float>(exponent) + t * (1.3465557f - 0.3465557f * t);
}

inline Eigen::Vector3f unpackTexel(std::uint32_t t) {
  return {static_cast<float>(t & 0xffu), static_cast<float>((t >> 8) & 0xffu),
          static_cast<float>((t >> 16) & 0xffu)};
}

}  // namespace detail

inline std::uint32_t MipTexture::bilinear(const Level& lv, float u, float v) const {
  constexpr std::uint32_t kEvenBytes = 0x00ff00ffu;  // R and B lanes of a packed texel
  const float x = u - 0.5f, y = v - 0.5f;
  const int xi = detail::floorToInt(x), yi = detail::floorToInt(y);
  // 8-bit fixed-point weights summing to exactly 256, so each 16-bit lane of the packed sums
  // stays below 2^16 (255 * 256).
  const std::uint32_t wx = static_cast<std::uint32_t>((x - static_cast<float>(xi)) * 256.0f);
  const std::uint32_t wy = static_cast<std::uint32_t>((y - static_cast<float>(yi)) * 256.0f);
  const std::uint32_t w11 = (wx * wy) >> 8, w01 = (wx * (256 - wy)) >> 8;
  const std::uint32_t w10 = ((256 - wx) * wy) >> 8, w00 = 256 - w01 - w10 - w11;
  const std::size_t s = static_cast<std::size_t>(lv.size);
  const std::size_t x0 = static_cast<std::size_t>(xi & lv.mask);
  const std::size_t x1 = static_cast<std::size_t>((xi + 1) & lv.mask);
  const std::size_t r0 = static_cast<std::size_t>(yi & lv.mask) * s;
  const std::size_t r1 = static_cast<std::size_t>((yi + 1) & lv.mask) * s;
  const std::uint32_t* t = lv.texels.data();
  const std::uint32_t t00 = t[r0 + x0], t01 = t[r0 + x1], t10 = t[r1 + x0], t11 = t[r1 + x1];
  const std::uint32_t rb = (((t00 & kEvenBytes) * w00 + (t01 & kEvenBytes) * w01 +
                             (t10 & kEvenBytes) * w10 + (t11 & kEvenBytes) * w11) >> 8) & kEvenBytes;
  const std::uint32_t g = ((((t00 >> 8) & kEvenBytes) * w00 + ((t01 >> 8) & kEvenBytes) * w01 +
                            ((t10 >> 8) & kEvenBytes) * w10 + ((t11 >> 8) & kEvenBytes) * w11) >> 8) &
                          0xffu;
  return rb | g << 8;
}

inline Eigen::Vector3f MipTexture::sample(double u, double v, float lod) const {
  const float uf = detail::wrapPeriod(u, period_, inv_period_);
  const float vf = detail::wrapPeriod(v, period_, inv_period_);
  const int top = levels() - 1;
  if (!(lod > 0.0f)) return detail::unpackTexel(bilinear(levels_[0], uf, vf));  // also NaN
  if (lod >= static_cast<float>(top)) {
    const float s = scale_[static_cast<std::size_t>(top)];
    return detail::unpackTexel(bilinear(levels_[static_cast<std::size_t>(top)], uf * s, vf * s));
  }
  const int l = static_cast<int>(lod);
  const float f = lod - static_cast<float>(l);
  const float s0 = scale_[static_cast<std::size_t>(l)], s1 = 0.5f * s0;
  const Eigen::Vector3f c0 =
      detail::unpackTexel(bilinear(levels_[static_cast<std::size_t>(l)], uf * s0, vf * s0));
  const Eigen::Vector3f c1 =
      detail::unpackTexel(bilinear(levels_[static_cast<std::size_t>(l + 1)], uf * s1, vf * s1));
  return c0 + f * (c1 - c0);
}

inline Eigen::Vector3f TextureBank::sample(const MaterialAppearance& appearance,
                                           const Eigen::Vector2d& uv_m, double footprint_m) const {
  double a = uv_m.x(), b = uv_m.y();
  if (appearance.orientation & 4) a = -a;
  switch (appearance.orientation & 3) {
    case 1: std::swap(a, b); a = -a; break;
    case 2: a = -a; b = -b; break;
    case 3: std::swap(a, b); b = -b; break;
    default: break;
  }
  // Surface v points up (world z on vertical faces) while image rows go down: negate v so the
  // texture is upright.
  const double u = (a + appearance.offset_m.x()) * inv_texel_;
  const double v = (appearance.offset_m.y() - b) * inv_texel_;
  const float lod = detail::fastLog2(static_cast<float>(footprint_m * inv_texel_));
  const Eigen::Vector3f c = textures_[static_cast<std::size_t>(appearance.texture)].sample(u, v, lod);
  return c.cwiseProduct(appearance.gain);
}

}  // namespace rgbdi::sim
