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
#include <map>
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
    std::vector<std::uint8_t> rgb;  ///< size*size*3, row-major
  };
  Eigen::Vector3f bilinear(const Level& lv, float u, float v) const;
  std::vector<Level> levels_;
  std::vector<float> scale_;  ///< texel coordinate scale of each level (2^-level)
  int size0_ = 0;
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
  std::vector<MipTexture> textures_;
  std::map<std::pair<int, int>, int> index_;  ///< (style, variant) -> texture
};

}  // namespace rgbdi::sim
