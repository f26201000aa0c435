#include "rgbdi/mapping/trajectory_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

#include "rgbdi/common/atomic_file.h"

namespace rgbdi::mapping {
namespace {

// Layout of the image around the two square panels [px].
constexpr int kMarginLeft = 70;
constexpr int kMarginRight = 20;
constexpr int kTitleHeight = 40;
constexpr int kTickLabelHeight = 30;
constexpr int kLegendHeight = 70;
/// Smallest world span shown by a panel axis [m] (a robot at rest still gets a readable plot).
constexpr double kMinSpan = 0.2;
constexpr double kPadding = 1.1;  ///< world span shown = data span x this
constexpr int kSubpixelBits = 4;  ///< cv::line shift: 1/16 px precision

const cv::Scalar kWhite(255, 255, 255);
const cv::Scalar kFrameGrey(120, 120, 120);
const cv::Scalar kGridGrey(225, 225, 225);
const cv::Scalar kText(30, 30, 30);
const cv::Scalar kGroundTruthGrey(90, 90, 90);
const cv::Scalar kEstimateBlue(200, 90, 20);  // BGR
const cv::Scalar kUnmatchedBlue(230, 190, 150);
const cv::Scalar kStartGreen(40, 170, 40);
const cv::Scalar kEndRed(40, 40, 210);

void checkTrajectory(const Trajectory& t, const std::string& path, const char* which) {
  for (std::size_t k = 0; k < t.size(); ++k)
    if (!std::isfinite(t[k].t) || !t[k].p.allFinite())
      throw std::invalid_argument("plotTrajectory " + path + ": " + which + " pose " +
                                  std::to_string(k) + " is not finite");
}

/// Index of the ground-truth pose nearest in time to t, or -1 when none is within max_dt.
long nearestStamp(const Trajectory& gt, double t, double max_dt) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t,
                                   [](const StampedPose& s, double v) { return s.t < v; });
  long best = -1;
  double best_dt = max_dt;
  for (auto c : {it, it == gt.begin() ? gt.end() : it - 1}) {
    if (c == gt.end()) continue;
    const double dt = std::abs(c->t - t);
    if (dt <= best_dt) {
      best_dt = dt;
      best = static_cast<long>(c - gt.begin());
    }
  }
  return best;
}

double niceStep(double span) {
  const double raw = span / 5.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw) return m * decade;
  return 10.0 * decade;
}

cv::Point subpixel(const Eigen::Vector2d& px) {
  const double s = 1 << kSubpixelBits;
  return {static_cast<int>(std::lround(px.x() * s)), static_cast<int>(std::lround(px.y() * s))};
}

cv::Point pixel(const Eigen::Vector2d& px) {
  return {static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y()))};
}

std::string metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

void drawText(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.45) {
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, kText, 1, cv::LINE_AA);
}

void drawPanelFrame(cv::Mat& img, const PlotPanel& p) {
  const char* names = "xyz";
  const double span_h = p.area.width / p.px_per_m_h, span_v = p.area.height / p.px_per_m_v;
  const double step_h = niceStep(span_h), step_v = niceStep(span_v);
  for (double h = std::ceil(p.h_min / step_h) * step_h; h <= p.h_min + span_h; h += step_h) {
    const int col = p.area.x + static_cast<int>(std::lround((h - p.h_min) * p.px_per_m_h));
    cv::line(img, {col, p.area.y}, {col, p.area.y + p.area.height}, kGridGrey, 1);
    drawText(img, metres(std::abs(h) < 1e-12 ? 0.0 : h), {col - 10, p.area.br().y + 16}, 0.4);
  }
  for (double v = std::ceil(p.v_min / step_v) * step_v; v <= p.v_min + span_v; v += step_v) {
    const int row = p.area.br().y - static_cast<int>(std::lround((v - p.v_min) * p.px_per_m_v));
    cv::line(img, {p.area.x, row}, {p.area.br().x, row}, kGridGrey, 1);
    drawText(img, metres(std::abs(v) < 1e-12 ? 0.0 : v), {p.area.x - kMarginLeft + 5, row + 4},
             0.4);
  }
  cv::rectangle(img, p.area, kFrameGrey, 1);
  drawText(img, p.title, {p.area.x, kTitleHeight - 14}, 0.55);
  drawText(img, std::string(1, names[p.axis_h]) + " [m]", {p.area.br().x - 40, p.area.br().y + 28},
           0.4);
  drawText(img, std::string(1, names[p.axis_v]) + " [m]", {p.area.x + 4, p.area.y + 14}, 0.4);
}

}  // namespace

Eigen::Vector2d PlotPanel::toPixel(const Eigen::Vector3d& p) const {
  return {area.x + (p[axis_h] - h_min) * px_per_m_h,
          area.y + area.height - (p[axis_v] - v_min) * px_per_m_v};
}

TrajectoryPlotInfo plotTrajectory(const std::string& path, const Trajectory& estimate,
                                  const Trajectory* ground_truth,
                                  const TrajectoryPlotOptions& options,
                                  const std::string& alignment) {
  if (estimate.empty()) throw std::invalid_argument("plotTrajectory " + path + ": empty estimate");
  if (options.panel_px < 100)
    throw std::invalid_argument("plotTrajectory " + path + ": panel_px must be >= 100");
  checkTrajectory(estimate, path, "estimate");
  if (ground_truth) {
    checkTrajectory(*ground_truth, path, "ground-truth");
    for (std::size_t k = 1; k < ground_truth->size(); ++k)
      if ((*ground_truth)[k].t < (*ground_truth)[k - 1].t)
        throw std::invalid_argument("plotTrajectory " + path +
                                    ": ground-truth stamps decrease at pose " + std::to_string(k));
  }

  // Extent of everything drawn.
  Eigen::Vector3d lo = estimate.front().p, hi = estimate.front().p;
  auto extend = [&](const Trajectory& t) {
    for (const StampedPose& s : t) {
      lo = lo.cwiseMin(s.p);
      hi = hi.cwiseMax(s.p);
    }
  };
  extend(estimate);
  if (ground_truth) extend(*ground_truth);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);

  const int P = options.panel_px;
  TrajectoryPlotInfo info;
  info.width = 2 * (kMarginLeft + P + kMarginRight);
  info.height = kTitleHeight + P + kTickLabelHeight + kLegendHeight;

  // Top view: equal axes. Side view: same horizontal scale, vertical scale fitted to z (the
  // height drift of a ground robot would be invisible at equal scale).
  const double span_xy = kPadding * std::max({hi.x() - lo.x(), hi.y() - lo.y(), kMinSpan});
  const double span_z = kPadding * std::max(hi.z() - lo.z(), kMinSpan);
  PlotPanel& top = info.panels[0];
  top.area = cv::Rect(kMarginLeft, kTitleHeight, P, P);
  top.axis_h = 0;
  top.axis_v = 1;
  top.px_per_m_h = top.px_per_m_v = P / span_xy;
  top.h_min = centre.x() - span_xy / 2;
  top.v_min = centre.y() - span_xy / 2;
  top.title = "top view (x-y)";
  PlotPanel& side = info.panels[1];
  side.area = cv::Rect(2 * kMarginLeft + P + kMarginRight, kTitleHeight, P, P);
  side.axis_h = 0;
  side.axis_v = 2;
  side.px_per_m_h = top.px_per_m_h;
  side.h_min = top.h_min;
  side.px_per_m_v = P / span_z;
  side.v_min = centre.z() - span_z / 2;
  const double exaggeration = side.px_per_m_v / side.px_per_m_h;
  side.title = "side view (x-z)";
  if (exaggeration > 1.05) side.title += ", z exaggerated x" + metres(exaggeration);

  // Position error of each estimated pose against the nearest ground-truth stamp.
  std::vector<double> error(estimate.size(), -1.0);
  if (ground_truth && !ground_truth->empty()) {
    double sum_sq = 0.0;
    for (std::size_t k = 0; k < estimate.size(); ++k) {
      const long g = nearestStamp(*ground_truth, estimate[k].t, options.max_time_diff_s);
      if (g < 0) continue;
      error[k] = (estimate[k].p - (*ground_truth)[static_cast<std::size_t>(g)].p).norm();
      sum_sq += error[k] * error[k];
      info.max_error_m = std::max(info.max_error_m, error[k]);
      ++info.matched;
    }
    if (info.matched > 0) info.rmse_m = std::sqrt(sum_sq / static_cast<double>(info.matched));
  }
  cv::Mat ramp(1, 256, CV_8UC1), lut;
  for (int i = 0; i < 256; ++i) ramp.at<std::uint8_t>(0, i) = static_cast<std::uint8_t>(i);
  cv::applyColorMap(ramp, lut, cv::COLORMAP_TURBO);
  auto errorColour = [&](double e) {
    const double f = info.max_error_m > 0 ? e / info.max_error_m : 0.0;
    const cv::Vec3b c = lut.at<cv::Vec3b>(0, static_cast<int>(std::lround(255.0 * f)));
    return cv::Scalar(c[0], c[1], c[2]);
  };

  cv::Mat img(info.height, info.width, CV_8UC3, kWhite);
  for (const PlotPanel& panel : info.panels) {
    drawPanelFrame(img, panel);
    if (ground_truth)
      for (std::size_t k = 1; k < ground_truth->size(); ++k)
        cv::line(img, subpixel(panel.toPixel((*ground_truth)[k - 1].p)),
                 subpixel(panel.toPixel((*ground_truth)[k].p)), kGroundTruthGrey, 2, cv::LINE_AA,
                 kSubpixelBits);
    for (std::size_t k = 0; k < estimate.size(); ++k) {
      const std::size_t a = k == 0 ? 0 : k - 1;
      cv::Scalar colour = kEstimateBlue;
      if (ground_truth) colour = error[k] >= 0 ? errorColour(error[k]) : kUnmatchedBlue;
      cv::line(img, subpixel(panel.toPixel(estimate[a].p)), subpixel(panel.toPixel(estimate[k].p)),
               colour, 2, cv::LINE_AA, kSubpixelBits);
    }
    cv::circle(img, pixel(panel.toPixel(estimate.front().p)), 6, kStartGreen, 2, cv::LINE_AA);
    const cv::Point end = pixel(panel.toPixel(estimate.back().p));
    cv::rectangle(img, end - cv::Point(5, 5), end + cv::Point(5, 5), kEndRed, 2, cv::LINE_AA);
  }

  // Legend.
  const int y0 = kTitleHeight + P + kTickLabelHeight + 18;
  int x = kMarginLeft;
  drawText(img, "o start   [] end", {x, y0});
  x += 160;
  if (ground_truth) {
    cv::line(img, {x, y0 - 4}, {x + 30, y0 - 4}, kGroundTruthGrey, 2);
    drawText(img, "ground truth", {x + 36, y0});
    x += 160;
    drawText(img, "estimate, position error:", {x, y0});
    x += 200;
    for (int i = 0; i < 200; ++i) {
      const cv::Vec3b c = lut.at<cv::Vec3b>(0, i * 255 / 199);
      cv::line(img, {x + i, y0 - 12}, {x + i, y0 + 2}, cv::Scalar(c[0], c[1], c[2]), 1);
    }
    drawText(img, "0", {x - 12, y0 + 18}, 0.4);
    drawText(img, metres(info.max_error_m) + " m", {x + 185, y0 + 18}, 0.4);
    drawText(img,
             "matched " + std::to_string(info.matched) + " of " + std::to_string(estimate.size()) +
                 " poses, RMSE " + metres(info.rmse_m) + " m, max " + metres(info.max_error_m) +
                 " m (" + alignment + ")",
             {kMarginLeft, y0 + 38});
  } else {
    cv::line(img, {x, y0 - 4}, {x + 30, y0 - 4}, kEstimateBlue, 2);
    drawText(img, "estimate", {x + 36, y0});
  }

  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", img, png))
    throw IoError(path + ": OpenCV could not encode the trajectory plot");
  writeFileAtomically(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
  return info;
}

}  // namespace rgbdi::mapping
