// Wooden planks of random widths and lengths, with grain lines, knots and dark joints.
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {

void paintPlanks(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  const cv::Scalar joint = hsv(r.uniform(15, 35), r.uniform(0.3, 0.7), r.uniform(0.05, 0.15));
  p.rect(0, 0, n, n, joint);
  const double hue = r.uniform(15, 40);
  const double gap = std::max(1.0, 0.003 * tpm);
  double y = 0;
  for (double rh : splitPeriod(r, n, 0.09 * tpm, 0.2 * tpm)) {
    double x = r.uniform(0, n);
    for (double len : splitPeriod(r, n, 0.5 * tpm, 1.8 * tpm)) {
      const cv::Scalar c = hsv(hue + r.uniform(-8, 8), r.uniform(0.35, 0.8), r.uniform(0.3, 0.9));
      p.rect(x, y, len - gap, rh - gap, c);
      // Grain: wavy lines along the plank.
      for (int g = r.integer(5, 14); g > 0; --g) {
        double gx = x, gy = y + r.uniform(0.1, 0.9) * (rh - gap);
        const cv::Scalar gc = scaled(c, r.uniform(0.6, 0.85));
        while (gx < x + len - gap) {
          const double step = std::min(r.uniform(0.05, 0.2) * tpm, x + len - gap - gx);
          const double ny =
              std::clamp(gy + r.uniform(-0.006, 0.006) * tpm, y + 1, y + rh - gap - 1);
          p.line(gx, gy, gx + step, ny, 1, gc);
          gx += step;
          gy = ny;
        }
      }
      for (int k = r.integer(0, 3); k > 0; --k) {  // knots
        const double kx = x + r.uniform(0.05, 0.95) * (len - gap);
        const double ky = y + r.uniform(0.2, 0.8) * (rh - gap);
        const double kr = r.uniform(0.006, 0.02) * tpm;
        p.ellipse(kx, ky, kr * 1.6, kr, r.uniform(-15, 15), scaled(c, 0.45));
        p.ellipse(kx, ky, kr * 0.8, kr * 0.5, 0, scaled(c, 0.25));
      }
      x += len;
    }
    y += rh;
  }
}

}  // namespace rgbdi::sim::detail
