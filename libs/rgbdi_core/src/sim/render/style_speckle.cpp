// Concrete/ceiling: blotches at three scales, cracks, and fixtures (vents, lamps, boxes).
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {

void paintSpeckle(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  const cv::Scalar base = hsv(r.uniform(0, 360), r.uniform(0, 0.15), r.uniform(0.6, 0.85));
  p.rect(0, 0, n, n, base);
  const double area_m2 = (n / tpm) * (n / tpm);
  struct Scale {
    double per_m2, r_lo, r_hi, contrast;
  };
  for (const Scale& s :
       {Scale{3, 0.1, 0.4, 0.12}, Scale{40, 0.02, 0.08, 0.35}, Scale{250, 0.004, 0.015, 0.6}}) {
    for (int i = 0; i < static_cast<int>(area_m2 * s.per_m2); ++i) {
      const double f = 1.0 + r.uniform(-s.contrast, s.contrast);
      p.ellipse(r.uniform(0, n), r.uniform(0, n), r.uniform(s.r_lo, s.r_hi) * tpm,
                r.uniform(s.r_lo, s.r_hi) * tpm, r.uniform(0, 180), scaled(base, f));
    }
  }
  for (int i = 0; i < static_cast<int>(area_m2 * 2); ++i) {  // cracks
    double x = r.uniform(0, n), y = r.uniform(0, n), a = r.uniform(0, 2 * M_PI);
    for (int k = r.integer(4, 12); k > 0; --k) {
      const double len = r.uniform(0.02, 0.08) * tpm;
      a += r.uniform(-0.8, 0.8);
      p.line(x, y, x + len * std::cos(a), y + len * std::sin(a), 1, scaled(base, 0.35));
      x += len * std::cos(a);
      y += len * std::sin(a);
    }
  }
  for (int i = 0; i < static_cast<int>(area_m2 * 1.5); ++i) {  // vents, lamps, junction boxes
    const double w = r.uniform(0.1, 0.6) * tpm, h = r.uniform(0.1, 0.6) * tpm;
    const double x = r.uniform(0, n), y = r.uniform(0, n);
    const cv::Scalar c = contrastingColor(r, base, 50);
    p.rect(x, y, w, h, c);
    const cv::Scalar slot = contrastingColor(r, c, 80);
    const int slots = r.integer(2, 8);
    for (int k = 0; k < slots; ++k)
      p.rect(x + 0.1 * w, y + (k + 0.5) * h / slots - 0.15 * h / slots, 0.8 * w, 0.3 * h / slots,
             slot);
  }
}

}  // namespace rgbdi::sim::detail
