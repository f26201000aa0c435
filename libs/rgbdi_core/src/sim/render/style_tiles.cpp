// Floor of irregular rectangular tiles (recursive splits, so joints form T-junctions and
// corners at many scales) with speckles, insets and scuffs.
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {
namespace {

struct TileContext {
  WrapPainter& p;
  DetRandom& r;
  double tpm;
  std::vector<cv::Scalar> palette;
  double grout;
};

void tile(TileContext& t, double x, double y, double w, double h) {
  const double min_size = 0.1 * t.tpm, max_size = 0.5 * t.tpm;
  const double longest = std::max(w, h);
  if (longest > 2 * min_size && (longest > max_size || t.r.chance(0.35))) {
    // Split the longer side at a random position away from the ends.
    if (w >= h) {
      const double s = t.r.uniform(min_size, w - min_size);
      tile(t, x, y, s, h);
      tile(t, x + s, y, w - s, h);
    } else {
      const double s = t.r.uniform(min_size, h - min_size);
      tile(t, x, y, w, s);
      tile(t, x, y + s, w, h - s);
    }
    return;
  }
  const cv::Scalar base =
      t.palette[static_cast<std::size_t>(t.r.integer(0, static_cast<int>(t.palette.size()) - 1))];
  const cv::Scalar c = scaled(base, t.r.uniform(0.8, 1.2));
  const double g = t.grout;
  t.p.rect(x + g, y + g, w - 2 * g, h - 2 * g, c);
  if (t.r.chance(0.3)) {
    const double m = std::min(w, h) * t.r.uniform(0.15, 0.3);
    t.p.rect(x + m, y + m, w - 2 * m, h - 2 * m, contrastingColor(t.r, c, 50));
  }
  if (t.r.chance(0.4)) {
    const cv::Scalar dot = contrastingColor(t.r, c, 60);
    const int dots = t.r.integer(3, 15);
    for (int i = 0; i < dots; ++i) {
      const double rad = t.r.uniform(0.003, 0.012) * t.tpm;
      t.p.ellipse(x + t.r.uniform(2 * g, w - 2 * g), y + t.r.uniform(2 * g, h - 2 * g), rad,
                  rad * t.r.uniform(0.6, 1.0), t.r.uniform(0, 180), dot);
    }
  }
}

}  // namespace

void paintTiles(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  TileContext t{p, r, tpm, {}, std::max(1.0, 0.004 * tpm)};
  for (int i = r.integer(4, 6); i > 0; --i)
    t.palette.push_back(hsv(r.uniform(0, 60), r.uniform(0.0, 0.5), r.uniform(0.15, 0.95)));
  p.rect(0, 0, n, n, hsv(r.uniform(0, 60), r.uniform(0, 0.2), r.uniform(0.1, 0.3)));  // grout
  tile(t, 0, 0, n, n);
  // Scuffs and debris on top of the tiles.
  const double area_m2 = (n / tpm) * (n / tpm);
  for (int i = 0; i < static_cast<int>(area_m2 * 8); ++i) {
    const double x = r.uniform(0, n), y = r.uniform(0, n);
    const double len = r.uniform(0.03, 0.2) * tpm, a = r.uniform(0, 2 * M_PI);
    p.line(x, y, x + len * std::cos(a), y + len * std::sin(a), r.integer(1, 3),
           hsv(0, 0, r.chance(0.5) ? r.uniform(0.02, 0.2) : r.uniform(0.8, 1.0)));
  }
}

}  // namespace rgbdi::sim::detail
