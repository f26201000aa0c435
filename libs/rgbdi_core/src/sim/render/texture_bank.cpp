#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/texture.h"
#include "sim/render/det_random.h"

namespace rgbdi::sim {

std::string toString(TextureStyle style) {
  switch (style) {
    case TextureStyle::Posters:
      return "posters";
    case TextureStyle::Bricks:
      return "bricks";
    case TextureStyle::Tiles:
      return "tiles";
    case TextureStyle::Shelves:
      return "shelves";
    case TextureStyle::Speckle:
      return "speckle";
    case TextureStyle::Planks:
      return "planks";
  }
  return "unknown";
}

TextureBank::TextureBank(std::uint64_t seed, const TextureOptions& options)
    : seed_(seed), options_(options), inv_texel_(1.0 / options.texel_size_m) {
  if (!(options.texel_size_m > 0.0) || !std::isfinite(options.texel_size_m))
    throw std::invalid_argument("TextureOptions: texel_size_m must be positive");
  if (options.size_log2 < 4 || options.size_log2 > 13)
    throw std::invalid_argument("TextureOptions: size_log2 must be in [4, 13]");
  if (options.variants_per_style < 1 || options.variants_per_style > 64)
    throw std::invalid_argument("TextureOptions: variants_per_style must be in [1, 64]");
  if (!(options.contrast > 0.0 && options.contrast <= 1.0))
    throw std::invalid_argument("TextureOptions: contrast must be in (0, 1]");
}

MaterialAppearance TextureBank::resolve(const Material& material) {
  detail::DetRandom rnd(material.seed);
  const int variant = rnd.integer(0, options_.variants_per_style - 1);
  const auto key = std::make_pair(static_cast<int>(material.style), variant);
  auto it = index_.find(key);
  if (it == index_.end()) {
    const int size = 1 << options_.size_log2;
    const std::uint64_t tex_seed =
        detail::mixSeed(seed_, static_cast<std::uint64_t>(key.first * 64 + key.second));
    cv::Mat texture = generateTexture(material.style, size, options_.texel_size_m, tex_seed);
    if (options_.contrast != 1.0) scaleTextureContrast(texture, options_.contrast);
    textures_.emplace_back(texture);
    it = index_.emplace(key, static_cast<int>(textures_.size() - 1)).first;
  }
  MaterialAppearance a;
  a.texture = it->second;
  const double period = options_.texel_size_m * (1 << options_.size_log2);
  a.offset_m = {rnd.uniform(0.0, period), rnd.uniform(0.0, period)};
  // Styles with a natural "up" (brick courses, shelves, planks, poster text) are only mirrored
  // left-right; the others may also be turned by quarter turns.
  const bool upright =
      material.style == TextureStyle::Bricks || material.style == TextureStyle::Shelves ||
      material.style == TextureStyle::Planks || material.style == TextureStyle::Posters;
  a.orientation = upright ? (rnd.chance(0.5) ? 4 : 0) : rnd.integer(0, 7);
  const float brightness = static_cast<float>(rnd.uniform(0.9, 1.1));
  for (int c = 0; c < 3; ++c) a.gain[c] = brightness * static_cast<float>(rnd.uniform(0.9, 1.1));
  return a;
}

MaterialAppearance mirroredAppearance(const MaterialAppearance& a, double mirror_length_m) {
  // sample() maps (u, v) to M (u, v) + offset with M the orientation's linear map. For
  // u' = L - u: M S (u', v) + M (L, 0) + offset, S = diag(-1, 1). M S is the orientation with the
  // mirror bit toggled (the mirror is applied first); M (L, 0) moves into the offset.
  MaterialAppearance m = a;
  m.orientation = a.orientation ^ 4;
  double du = mirror_length_m, dv = 0.0;
  orientSurfaceCoordinates(a.orientation, du, dv);
  m.offset_m += Eigen::Vector2d(du, -dv);  // sample() negates the v offset term
  return m;
}

}  // namespace rgbdi::sim
