// Office/corridor wall: painted plaster with overlapping posters, notices and sticky notes.
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {

void paintPosters(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  const cv::Scalar wall = hsv(r.uniform(0, 360), r.uniform(0.0, 0.25), r.uniform(0.7, 0.9));
  p.rect(0, 0, n, n, wall);
  // Large faint stains break up the plain paint between posters.
  for (int i = 0; i < 40; ++i)
    p.ellipse(r.uniform(0, n), r.uniform(0, n), r.uniform(0.1, 0.4) * tpm,
              r.uniform(0.1, 0.4) * tpm, r.uniform(0, 180), scaled(wall, r.uniform(0.9, 1.08)));
  const double area_m2 = (n / tpm) * (n / tpm);
  const int posters = static_cast<int>(area_m2 * 3.0);
  for (int i = 0; i < posters; ++i) {
    const double w = r.uniform(0.2, 0.9) * tpm;
    const double h = w * r.uniform(0.6, 1.5);
    paintPoster(p, r, r.uniform(0, n), r.uniform(0, n), w, h, tpm);
  }
  // Sticky notes, switches, labels: small high-contrast patches at a finer scale.
  const int notes = static_cast<int>(area_m2 * 16);
  for (int i = 0; i < notes; ++i) {
    const double s = r.uniform(0.04, 0.1) * tpm;
    const double x = r.uniform(0, n), y = r.uniform(0, n);
    const cv::Scalar c = hsv(r.uniform(0, 360), r.uniform(0.3, 1.0), r.uniform(0.3, 1.0));
    p.rect(x, y, s, s * r.uniform(0.7, 1.4), c);
    if (r.chance(0.6))
      paintText(p, r, x + 0.1 * s, y + 0.15 * s, 0.8 * s, 0.7 * s, 0.12 * s,
                contrastingColor(r, c, 70));
  }
}

}  // namespace rgbdi::sim::detail
