// Cluttered shelving: uprights and boards at irregular spacing, filled with books, boxes and
// stacks of different sizes and colours.
#include "sim/render/texture_styles.h"

namespace rgbdi::sim::detail {
namespace {

void fillCompartment(WrapPainter& p, DetRandom& r, double x0, double x1, double y_top,
                     double y_bottom, double tpm) {
  const double gap = y_bottom - y_top;
  double x = x0 + r.uniform(0, 0.03) * tpm;
  while (x < x1) {
    const double kind = r.uniform();
    double w;
    if (kind < 0.55) {  // book standing upright
      w = r.uniform(0.015, 0.06) * tpm;
      const double h = gap * r.uniform(0.55, 0.95);
      const cv::Scalar c = randomColor(r);
      const double wc = std::min(w, x1 - x);
      p.rect(x, y_bottom - h, wc, h, c);
      if (r.chance(0.6))  // spine label
        p.rect(x + 0.15 * wc, y_bottom - h * r.uniform(0.3, 0.8), 0.7 * wc, h * 0.1,
               contrastingColor(r, c, 60));
    } else if (kind < 0.8) {  // box with a label and printing
      w = r.uniform(0.08, 0.3) * tpm;
      const double h = gap * r.uniform(0.3, 0.9);
      const cv::Scalar c = randomColor(r);
      const double wc = std::min(w, x1 - x);
      p.rect(x, y_bottom - h, wc, h, c);
      const cv::Scalar lc = contrastingColor(r, c, 70);
      p.rect(x + 0.2 * wc, y_bottom - 0.8 * h, 0.5 * wc, 0.3 * h, lc);
      paintText(p, r, x + 0.25 * wc, y_bottom - 0.75 * h, 0.4 * wc, 0.2 * h,
                std::max(1.0, 0.005 * tpm), contrastingColor(r, lc, 70));
    } else if (kind < 0.92) {  // stack of lying books
      w = r.uniform(0.15, 0.3) * tpm;
      double y = y_bottom;
      const double top = y_bottom - gap * r.uniform(0.3, 0.85);
      while (y > top) {
        const double th = r.uniform(0.02, 0.05) * tpm;
        const double bw = std::min(w * r.uniform(0.8, 1.0), x1 - x);
        p.rect(x, y - th, bw, th, randomColor(r));
        y -= th;
      }
    } else {  // empty space
      w = r.uniform(0.02, 0.12) * tpm;
    }
    x += w;
  }
}

}  // namespace

void paintShelves(WrapPainter& p, DetRandom& r, double tpm) {
  const double n = p.size();
  const cv::Scalar back = hsv(r.uniform(0, 360), r.uniform(0, 0.3), r.uniform(0.08, 0.25));
  const cv::Scalar frame = hsv(r.uniform(20, 40), r.uniform(0.1, 0.6), r.uniform(0.45, 0.85));
  p.rect(0, 0, n, n, back);
  const double board = 0.025 * tpm, upright = 0.035 * tpm;
  const std::vector<double> cols = splitPeriod(r, n, 0.6 * tpm, 1.2 * tpm);
  const std::vector<double> rows = splitPeriod(r, n, 0.28 * tpm, 0.45 * tpm);
  double x = 0;
  for (double cw : cols) {
    double y = 0;
    for (double rh : rows) {
      fillCompartment(p, r, x + upright, x + cw, y + board, y + rh, tpm);
      p.rect(x, y + rh - board * 0.2, cw, board, frame);  // board under the items
      y += rh;
    }
    p.rect(x, 0, upright, n, scaled(frame, 0.85));
    x += cw;
  }
}

}  // namespace rgbdi::sim::detail
