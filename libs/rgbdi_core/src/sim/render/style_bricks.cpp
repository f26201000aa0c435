// Brick wall with irregular brick lengths and colours, a few signs and paint marks.
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {

void paintBricks(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  const cv::Scalar mortar = hsv(r.uniform(20, 50), r.uniform(0.0, 0.2), r.uniform(0.55, 0.8));
  p.rect(0, 0, n, n, mortar);
  const double hue = r.uniform(0, 40), sat = r.uniform(0.35, 0.75), val = r.uniform(0.35, 0.6);
  // Courses of unequal height (reclaimed bricks, re-laid patches): equal courses would make the
  // wall periodic every 7.5 cm vertically, where KLT could lock onto the wrong course.
  const double joint = 0.01 * tpm;
  double y = 0.0;
  for (double pitch : splitPeriod(r, n, 0.055 * tpm, 0.1 * tpm)) {
    const double start = r.uniform(0, n);
    double x = start;
    for (double len : splitPeriod(r, n, 0.17 * tpm, 0.27 * tpm)) {
      cv::Scalar color;
      if (r.chance(0.08))
        color = hsv(r.uniform(0, 60), r.uniform(0, 0.3), r.uniform(0.1, 0.95));  // odd brick
      else
        color = hsv(hue + r.uniform(-8, 8), sat * r.uniform(0.8, 1.2), val * r.uniform(0.65, 1.4));
      p.rect(x, y, len - joint, pitch - joint, color);
      // Chips and soot spots on the brick face.
      const int spots = r.integer(0, 3);
      for (int s = 0; s < spots; ++s)
        p.ellipse(x + r.uniform(0, len - joint), y + r.uniform(0, pitch - joint),
                  r.uniform(0.003, 0.012) * tpm, r.uniform(0.003, 0.01) * tpm, r.uniform(0, 180),
                  scaled(color, r.uniform(0.4, 0.75)));
      x += len;
    }
    y += pitch;
  }
  const double area_m2 = (n / tpm) * (n / tpm);
  for (int i = 0; i < static_cast<int>(area_m2 * 0.6); ++i) {
    const double w = r.uniform(0.2, 0.6) * tpm;
    paintPoster(p, r, r.uniform(0, n), r.uniform(0, n), w, w * r.uniform(0.5, 1.3), tpm);
  }
  // Paint strokes: long thick polylines, strong colours.
  for (int i = 0; i < static_cast<int>(area_m2 * 1.0); ++i) {
    const cv::Scalar c = hsv(r.uniform(0, 360), r.uniform(0.5, 1.0), r.uniform(0.4, 1.0));
    double x = r.uniform(0, n), y0 = r.uniform(0, n);
    const int thick = std::max(2, static_cast<int>(r.uniform(0.008, 0.025) * tpm));
    for (int k = r.integer(2, 6); k > 0; --k) {
      const double nx = x + r.uniform(-0.25, 0.25) * tpm, ny = y0 + r.uniform(-0.2, 0.2) * tpm;
      p.line(x, y0, nx, ny, thick, c);
      x = nx;
      y0 = ny;
    }
  }
}

}  // namespace rgbdi::sim::detail
