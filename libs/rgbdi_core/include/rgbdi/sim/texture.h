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
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rgbdi::sim {

enum class TextureStyle { Posters, Bricks, Tiles, Shelves, Speckle, Planks };
constexpr int kTextureStyleCount = 6;
std::string toString(TextureStyle style);

struct TextureOptions {
  double texel_size_m = 0.004;  ///< [m] world size of one finest-level texel
  int size_log2 = 10;  ///< textures are 2^size_log2 texels square (period 4.1 m at defaults)
  int variants_per_style = 2;  ///< distinct generated textures per style
  /// (0, 1]: every generated texture's deviation from its mean colour is scaled by this
  /// (1 = as generated; low = faint texture, fewer corners).
  double contrast = 1.0;
};

/// Generates one periodic (seamlessly wrapping) texture: CV_8UC3, R,G,B order, size x size.
/// Same (style, size, texel, seed) -> identical bytes.
cv::Mat generateTexture(TextureStyle style, int size, double texel_size_m, std::uint64_t seed);

/// Scales every texel's deviation from the texture's mean colour (per channel, the mean of all
/// texels) by `contrast`, rounding to the nearest level: texel' = mean + contrast (texel - mean).
/// CV_8UC3; throws std::invalid_argument otherwise or unless 0 < contrast <= 1.
void scaleTextureContrast(cv::Mat& texture, double contrast);

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
    /// size*size texels, row-major, packed R | G << 8 | B << 16 (one load per texel; the
    /// filter unpacks a texel's three channels at once).
    std::vector<std::uint32_t> texels;
  };
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
  int texture = 0;                                     ///< index into TextureBank
  Eigen::Vector2d offset_m = Eigen::Vector2d::Zero();  ///< [m] shift of the surface coordinates
  int orientation = 0;  ///< 0..7: quarter turns (bits 0-1) and mirror (bit 2)
  Eigen::Vector3f gain = Eigen::Vector3f::Ones();  ///< per-channel colour gain
};

/// Applies a MaterialAppearance::orientation to surface coordinates (a, b): the mirror (bit 2)
/// negates a, then bits 0-1 turn by quarter turns.
inline void orientSurfaceCoordinates(int orientation, double& a, double& b) {
  if (orientation & 4) a = -a;
  switch (orientation & 3) {
    case 1:
      std::swap(a, b);
      a = -a;
      break;
    case 2:
      a = -a;
      b = -b;
      break;
    case 3:
      std::swap(a, b);
      b = -b;
      break;
    default:
      break;
  }
}

/// The appearance that shows at surface coordinates (L - u, v) what `a` shows at (u, v): the
/// same texture, gain and (un-mirrored) orientation, seen mirrored about u = L / 2. Two facing
/// walls of a room whose u axes both run along the same world axis then look identical from
/// viewpoints that are a half turn apart (the walls' appearance aliases).
MaterialAppearance mirroredAppearance(const MaterialAppearance& a, double mirror_length_m);

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

// Filtered colour R, G, B (and 0) in four float lanes: SSE2 registers where available (baseline
// on x86-64), otherwise a plain array with the same operations in the same order.
#if defined(__SSE2__)
using Rgb4 = __m128;
inline Rgb4 lerp4(Rgb4 a, Rgb4 b, float f) {
  return _mm_add_ps(a, _mm_mul_ps(_mm_set1_ps(f), _mm_sub_ps(b, a)));
}
inline Eigen::Vector3f toVector3(Rgb4 c) {
  alignas(16) float o[4];
  _mm_store_ps(o, c);
  return {o[0], o[1], o[2]};
}
// The four texels t00, t01, t10, t11 of a bilinear footprint, unpacked to float lanes.
inline void unpack4(std::uint32_t t00, std::uint32_t t01, std::uint32_t t10, std::uint32_t t11,
                    Rgb4 out[4]) {
  const __m128i zero = _mm_setzero_si128();
  const __m128i t = _mm_set_epi32(static_cast<int>(t11), static_cast<int>(t10),
                                  static_cast<int>(t01), static_cast<int>(t00));
  const __m128i first = _mm_unpacklo_epi8(t, zero), second = _mm_unpackhi_epi8(t, zero);
  out[0] = _mm_cvtepi32_ps(_mm_unpacklo_epi16(first, zero));
  out[1] = _mm_cvtepi32_ps(_mm_unpackhi_epi16(first, zero));
  out[2] = _mm_cvtepi32_ps(_mm_unpacklo_epi16(second, zero));
  out[3] = _mm_cvtepi32_ps(_mm_unpackhi_epi16(second, zero));
}
#else
struct Rgb4 {
  float v[4];
};
inline Rgb4 lerp4(const Rgb4& a, const Rgb4& b, float f) {
  Rgb4 r;
  for (int k = 0; k < 4; ++k) r.v[k] = a.v[k] + f * (b.v[k] - a.v[k]);
  return r;
}
inline Eigen::Vector3f toVector3(const Rgb4& c) { return {c.v[0], c.v[1], c.v[2]}; }
inline void unpack4(std::uint32_t t00, std::uint32_t t01, std::uint32_t t10, std::uint32_t t11,
                    Rgb4 out[4]) {
  const std::uint32_t t[4] = {t00, t01, t10, t11};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) out[i].v[k] = static_cast<float>((t[i] >> (8 * k)) & 0xffu);
}
#endif

// Bilinear filter of one level at texel coordinates (u, v) (texel centres at integer + 0.5),
// wrapping at the borders.
inline Rgb4 bilinear(const std::uint32_t* texels, int size, int mask, float u, float v) {
  const float x = u - 0.5f, y = v - 0.5f;
  const int xi = floorToInt(x), yi = floorToInt(y);
  const float ax = x - static_cast<float>(xi), ay = y - static_cast<float>(yi);
  const std::size_t s = static_cast<std::size_t>(size);
  const std::size_t x0 = static_cast<std::size_t>(xi & mask);
  const std::size_t x1 = static_cast<std::size_t>((xi + 1) & mask);
  const std::size_t r0 = static_cast<std::size_t>(yi & mask) * s;
  const std::size_t r1 = static_cast<std::size_t>((yi + 1) & mask) * s;
  Rgb4 t[4];
  unpack4(texels[r0 + x0], texels[r0 + x1], texels[r1 + x0], texels[r1 + x1], t);
  return lerp4(lerp4(t[0], t[1], ax), lerp4(t[2], t[3], ax), ay);
}

}  // namespace detail

inline Eigen::Vector3f MipTexture::sample(double u, double v, float lod) const {
  const float uf = detail::wrapPeriod(u, period_, inv_period_);
  const float vf = detail::wrapPeriod(v, period_, inv_period_);
  const int top = levels() - 1;
  auto at = [&](int l, float scale) {
    const Level& lv = levels_[static_cast<std::size_t>(l)];
    return detail::bilinear(lv.texels.data(), lv.size, lv.mask, uf * scale, vf * scale);
  };
  if (!(lod > 0.0f)) return detail::toVector3(at(0, 1.0f));  // magnified (also catches NaN)
  if (lod >= static_cast<float>(top))
    return detail::toVector3(at(top, scale_[static_cast<std::size_t>(top)]));
  const int l = static_cast<int>(lod);
  const float s0 = scale_[static_cast<std::size_t>(l)];
  return detail::toVector3(
      detail::lerp4(at(l, s0), at(l + 1, 0.5f * s0), lod - static_cast<float>(l)));
}

inline Eigen::Vector3f TextureBank::sample(const MaterialAppearance& appearance,
                                           const Eigen::Vector2d& uv_m, double footprint_m) const {
  double a = uv_m.x(), b = uv_m.y();
  orientSurfaceCoordinates(appearance.orientation, a, b);
  // Surface v points up (world z on vertical faces) while image rows go down: negate v so the
  // texture is upright.
  const double u = (a + appearance.offset_m.x()) * inv_texel_;
  const double v = (appearance.offset_m.y() - b) * inv_texel_;
  const float lod = detail::fastLog2(static_cast<float>(footprint_m * inv_texel_));
  const Eigen::Vector3f c =
      textures_[static_cast<std::size_t>(appearance.texture)].sample(u, v, lod);
  return c.cwiseProduct(appearance.gain);
}

}  // namespace rgbdi::sim
