#include <cmath>
#include <stdexcept>

#include "rgbdi/sim/texture.h"
#include "sim/render/texture_styles.h"

namespace rgbdi::sim {
namespace detail {

std::vector<double> splitPeriod(DetRandom& r, double total, double lo, double hi) {
  std::vector<double> out;
  double used = 0.0;
  while (total - used > hi) {
    const double len = r.uniform(lo, hi);
    out.push_back(len);
    used += len;
  }
  const double rest = total - used;
  if (rest < 0.5 * lo && !out.empty())
    out.back() += rest;
  else
    out.push_back(rest);
  return out;
}

void paintText(WrapPainter& p, DetRandom& r, double x, double y, double w, double h,
               double line_height, const cv::Scalar& color) {
  const double pitch = line_height * r.uniform(1.5, 2.2);
  for (double ly = y; ly + line_height <= y + h; ly += pitch) {
    // Ragged right margin and occasional short last lines, as in real paragraphs.
    const double line_end = x + w * (r.chance(0.2) ? r.uniform(0.3, 0.8) : r.uniform(0.85, 1.0));
    double wx = x;
    while (wx < line_end) {
      const double word = line_height * r.uniform(0.8, 5.0);
      const double end = std::min(wx + word, line_end);
      // One block per word: its corners are what a tracker sees of text at a distance.
      p.rect(wx, ly, end - wx, line_height, color);
      wx = end + line_height * r.uniform(0.5, 1.0);
    }
  }
}

void paintPoster(WrapPainter& p, DetRandom& r, double x, double y, double w, double h, double tpm) {
  const cv::Scalar bg = randomColor(r);
  p.rect(x, y, w, h, bg);
  double m = 0.0;
  if (r.chance(0.5)) {
    m = r.uniform(0.005, 0.02) * tpm;
    const cv::Scalar frame = contrastingColor(r, bg, 50);
    p.rect(x, y, w, m, frame);
    p.rect(x, y + h - m, w, m, frame);
    p.rect(x, y, m, h, frame);
    p.rect(x + w - m, y, m, h, frame);
  }
  const double ix = x + m + 0.04 * w, iy = y + m + 0.04 * h;
  const double iw = w - 2 * m - 0.08 * w, ih = h - 2 * m - 0.08 * h;
  // Bold shapes in the upper part, text below.
  const double split = r.uniform(0.35, 0.7);
  const int shapes = r.integer(1, 5);
  for (int i = 0; i < shapes; ++i) {
    const cv::Scalar c = contrastingColor(r, bg, 60);
    const double sw = iw * r.uniform(0.15, 0.6), sh = ih * split * r.uniform(0.2, 0.9);
    const double sx = ix + r.uniform(0, iw - sw), sy = iy + r.uniform(0, ih * split - sh);
    switch (r.integer(0, 3)) {
      case 0:
        p.rect(sx, sy, sw, sh, c);
        break;
      case 1:
        p.ellipse(sx + sw / 2, sy + sh / 2, sw / 2, sh / 2, 0, c);
        break;
      case 2:
        p.polygon({{sx, sy + sh}, {sx + sw, sy + sh}, {sx + r.uniform(0, sw), sy}}, c);
        break;
      default: {
        // Bar chart.
        const int bars = r.integer(3, 8);
        const double bw = sw / (bars * 1.5);
        for (int b = 0; b < bars; ++b) {
          const double bh = sh * r.uniform(0.15, 1.0);
          p.rect(sx + b * 1.5 * bw, sy + sh - bh, bw, bh, c);
        }
      }
    }
  }
  if (r.chance(0.85)) {
    const double lh = r.uniform(0.006, 0.02) * tpm;
    paintText(p, r, ix, iy + ih * split + lh, iw, ih * (1 - split) - lh, lh,
              contrastingColor(r, bg, 80));
  }
}

}  // namespace detail

cv::Mat generateTexture(TextureStyle style, int size, double texel_size_m, std::uint64_t seed) {
  if (size < 16 || (size & (size - 1)) != 0)
    throw std::invalid_argument("generateTexture: size must be a power of two >= 16");
  if (!(texel_size_m > 0.0)) throw std::invalid_argument("generateTexture: texel size must be > 0");
  cv::Mat img(size, size, CV_8UC3, cv::Scalar::all(128));
  detail::WrapPainter painter(img);
  detail::DetRandom rnd(seed);
  const double tpm = 1.0 / texel_size_m;
  switch (style) {
    case TextureStyle::Posters:
      detail::paintPosters(painter, rnd, tpm);
      break;
    case TextureStyle::Bricks:
      detail::paintBricks(painter, rnd, tpm);
      break;
    case TextureStyle::Tiles:
      detail::paintTiles(painter, rnd, tpm);
      break;
    case TextureStyle::Shelves:
      detail::paintShelves(painter, rnd, tpm);
      break;
    case TextureStyle::Speckle:
      detail::paintSpeckle(painter, rnd, tpm);
      break;
    case TextureStyle::Planks:
      detail::paintPlanks(painter, rnd, tpm);
      break;
  }
  // Fine grain on every surface (paper fibre, paint roughness) so that even flat areas are not
  // perfectly uniform; the mip chain averages it away at a distance. cv::RNG keeps it
  // platform-independent.
  cv::Mat grain(size, size, CV_16SC1);
  cv::RNG cvrng(rnd.next());
  cvrng.fill(grain, cv::RNG::NORMAL, 0.0, 4.0);
  for (int y = 0; y < size; ++y) {
    std::uint8_t* row = img.ptr<std::uint8_t>(y);
    const std::int16_t* g = grain.ptr<std::int16_t>(y);
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 3; ++c)
        row[3 * x + c] = cv::saturate_cast<std::uint8_t>(row[3 * x + c] + g[x]);
  }
  return img;
}

}  // namespace rgbdi::sim
