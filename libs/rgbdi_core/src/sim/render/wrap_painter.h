// Drawing on a periodic canvas: every shape that crosses a border is drawn again shifted by
// the canvas size, so the texture wraps without seams. Coordinates are in texels.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "sim/render/det_random.h"

namespace rgbdi::sim::detail {

class WrapPainter {
 public:
  explicit WrapPainter(cv::Mat& canvas) : img_(canvas), n_(canvas.cols) {}
  int size() const { return n_; }
  cv::Mat& image() { return img_; }

  void rect(double x, double y, double w, double h, const cv::Scalar& c) {
    if (px(x + w) <= px(x) || px(y + h) <= px(y)) return;  // thinner than a texel
    forCopies(x, y, x + w, y + h, [&](int dx, int dy) {
      cv::rectangle(img_, cv::Point(px(x) + dx, px(y) + dy),
                    cv::Point(px(x + w) - 1 + dx, px(y + h) - 1 + dy), c, cv::FILLED, cv::LINE_8);
    });
  }
  void ellipse(double cx, double cy, double ax, double ay, double angle_deg, const cv::Scalar& c) {
    const double r = std::max(ax, ay);
    forCopies(cx - r, cy - r, cx + r, cy + r, [&](int dx, int dy) {
      cv::ellipse(img_, cv::Point(px(cx) + dx, px(cy) + dy),
                  cv::Size(std::max(1, px(ax)), std::max(1, px(ay))), angle_deg, 0, 360, c,
                  cv::FILLED, cv::LINE_8);
    });
  }
  void line(double x0, double y0, double x1, double y1, int thickness, const cv::Scalar& c) {
    forCopies(std::min(x0, x1) - thickness, std::min(y0, y1) - thickness,
              std::max(x0, x1) + thickness, std::max(y0, y1) + thickness, [&](int dx, int dy) {
                cv::line(img_, cv::Point(px(x0) + dx, px(y0) + dy),
                         cv::Point(px(x1) + dx, px(y1) + dy), c, thickness, cv::LINE_8);
              });
  }
  void polygon(const std::vector<cv::Point2d>& pts, const cv::Scalar& c) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const auto& p : pts) {
      x0 = std::min(x0, p.x);
      y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x);
      y1 = std::max(y1, p.y);
    }
    forCopies(x0, y0, x1, y1, [&](int dx, int dy) {
      std::vector<cv::Point> ip;
      ip.reserve(pts.size());
      for (const auto& p : pts) ip.emplace_back(px(p.x) + dx, px(p.y) + dy);
      cv::fillPoly(img_, std::vector<std::vector<cv::Point>>{ip}, c, cv::LINE_8);
    });
  }

 private:
  static int px(double v) { return static_cast<int>(std::lround(v)); }
  template <class Draw>
  void forCopies(double x0, double y0, double x1, double y1, Draw&& draw) {
    for (int ky = -1; ky <= 1; ++ky)
      for (int kx = -1; kx <= 1; ++kx) {
        const double sx = kx * n_, sy = ky * n_;
        if (x1 + sx < -1 || x0 + sx > n_ || y1 + sy < -1 || y0 + sy > n_) continue;
        draw(static_cast<int>(sx), static_cast<int>(sy));
      }
  }
  cv::Mat& img_;
  int n_;
};

/// HSV (h in degrees, s and v in [0, 1]) -> R,G,B scalar in [0, 255].
inline cv::Scalar hsv(double h, double s, double v) {
  h = std::fmod(std::fmod(h, 360.0) + 360.0, 360.0) / 60.0;
  const int i = static_cast<int>(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i) {
    case 1:
      r = q;
      g = v;
      b = p;
      break;
    case 2:
      r = p;
      g = v;
      b = t;
      break;
    case 3:
      r = p;
      g = q;
      b = v;
      break;
    case 4:
      r = t;
      g = p;
      b = v;
      break;
    case 5:
      r = v;
      g = p;
      b = q;
      break;
    default:
      break;
  }
  return {255 * r, 255 * g, 255 * b};
}

inline double luminance(const cv::Scalar& c) { return 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2]; }

/// Any colour (random hue, saturation, value).
inline cv::Scalar randomColor(DetRandom& r) {
  return hsv(r.uniform(0, 360), r.uniform(0.0, 1.0), r.uniform(0.08, 1.0));
}

/// A random colour whose luminance differs from `bg` by at least min_diff grey levels.
inline cv::Scalar contrastingColor(DetRandom& r, const cv::Scalar& bg, double min_diff = 70.0) {
  const double lb = luminance(bg);
  for (int tries = 0; tries < 32; ++tries) {
    const cv::Scalar c = randomColor(r);
    if (std::abs(luminance(c) - lb) >= min_diff) return c;
  }
  return lb > 127 ? hsv(r.uniform(0, 360), r.uniform(0, 1), r.uniform(0.05, 0.2))
                  : hsv(r.uniform(0, 360), r.uniform(0, 0.4), r.uniform(0.85, 1.0));
}

/// Colour scaled in brightness by factor (clamped).
inline cv::Scalar scaled(const cv::Scalar& c, double factor) {
  return {std::min(255.0, c[0] * factor), std::min(255.0, c[1] * factor),
          std::min(255.0, c[2] * factor)};
}

}  // namespace rgbdi::sim::detail
