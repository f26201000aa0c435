#include "rgbdi/frontend/depth_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

namespace rgbdi::frontend {
namespace {

/// "No depth point here" in the z-buffers: the neutral element of the minimum.
constexpr float kEmpty = std::numeric_limits<float>::max();

bool sameCamera(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.dist == b.dist;
}

[[noreturn]] void fail(const RgbdFrame& frame, const std::string& what) {
  const std::string where =
      frame.source_label.empty() ? "frame " + std::to_string(frame.index) : frame.source_label;
  throw std::invalid_argument("depth registration: " + where + ": " + what);
}

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

/// Largest squared normalised radius worth projecting: the polynomial distortion model is only
/// meaningful inside the field of view it was calibrated on and can fold far-away points back
/// into the image. The bound is the image border's radius with a margin of half again.
float maxNormalisedRadius2(const PinholeCamera& cam) {
  double r2 = 0.0;
  const double w = cam.width - 1, h = cam.height - 1;
  const double border[8][2] = {{0, 0},     {w, 0},     {0, h},     {w, h},
                               {w / 2, 0}, {w / 2, h}, {0, h / 2}, {w, h / 2}};
  for (const auto& p : border) r2 = std::max(r2, cam.pixelToNormalized({p[0], p[1]}).squaredNorm());
  return static_cast<float>(1.5 * r2);
}

/// Smallest valid raw depth value of the image (0 when there is none).
std::uint16_t smallestDepthValue(const cv::Mat& depth) {
  // Branch-free so the loop vectorises: d - 1 wraps 0 (no data) round to the largest value.
  std::uint16_t lowest_minus_one = std::numeric_limits<std::uint16_t>::max();
  for (int v = 0; v < depth.rows; ++v) {
    const std::uint16_t* row = depth.ptr<std::uint16_t>(v);
    for (int u = 0; u < depth.cols; ++u)
      lowest_minus_one = std::min(lowest_minus_one, static_cast<std::uint16_t>(row[u] - 1u));
  }
  return lowest_minus_one == std::numeric_limits<std::uint16_t>::max() ? 0 : lowest_minus_one + 1;
}

cv::Rect aroundPixel(const Eigen::Vector2d& centre, int radius) {
  const int u = static_cast<int>(std::lround(centre.x())),
            v = static_cast<int>(std::lround(centre.y()));
  return {u - radius, v - radius, 2 * radius + 1, 2 * radius + 1};
}

cv::Rect grown(const cv::Rect& r, int by) {
  return {r.x - by, r.y - by, r.width + 2 * by, r.height + 2 * by};
}

}  // namespace

DepthRegistrar::DepthRegistrar(const FrontendOptions& options) : options_(options) {
  options_.validate();
}

void DepthRegistrar::updateRays(const PinholeCamera& cam_depth) {
  if (!rays_xn_.empty() && sameCamera(cam_depth, rays_camera_)) return;
  rays_camera_ = cam_depth;
  rays_xn_.resize(static_cast<size_t>(cam_depth.width) * cam_depth.height * 2);
  size_t k = 0;
  for (int v = 0; v < cam_depth.height; ++v)
    for (int u = 0; u < cam_depth.width; ++u) {
      const Eigen::Vector2d xn = cam_depth.pixelToNormalized({double(u), double(v)});
      rays_xn_[k++] = static_cast<float>(xn.x());
      rays_xn_[k++] = static_cast<float>(xn.y());
    }
}

void DepthRegistrar::prepare(const RgbdFrame& frame, const PinholeCamera& cam_color) {
  if (!frame.hasDepth()) fail(frame, "no depth image");
  if (frame.depth.type() != CV_16UC1)
    fail(frame, "depth image must be CV_16UC1 (raw units), got OpenCV type " +
                    std::to_string(frame.depth.type()));
  if (!(frame.depth_unit_m > 0.0) || !std::isfinite(frame.depth_unit_m))
    fail(frame, "depth unit " + std::to_string(frame.depth_unit_m) + " m is not positive");
  if (!cam_color.valid()) fail(frame, "colour camera intrinsics are not valid");
  if (frame.depth_aligned_to_color) {
    if (frame.depth.cols != cam_color.width || frame.depth.rows != cam_color.height)
      fail(frame, "depth aligned to colour is " + sizeText(frame.depth.cols, frame.depth.rows) +
                      " but the colour camera is " + sizeText(cam_color.width, cam_color.height));
    return;
  }
  const PinholeCamera& cam_depth = frame.cam_depth;
  if (!cam_depth.valid())
    fail(frame, "depth is not aligned to colour but has no valid depth intrinsics");
  if (frame.depth.cols != cam_depth.width || frame.depth.rows != cam_depth.height)
    fail(frame, "depth image is " + sizeText(frame.depth.cols, frame.depth.rows) +
                    " but the depth camera is " + sizeText(cam_depth.width, cam_depth.height));
  if (!frame.T_color_depth.matrix().allFinite()) fail(frame, "T_color_depth is not finite");
  updateRays(cam_depth);
  if (!sameCamera(cam_color, cam_color_) || max_radius2_ == 0.0f) {
    cam_color_ = cam_color;
    max_radius2_ = maxNormalisedRadius2(cam_color);
  }
  R_color_depth_ = frame.T_color_depth.rotation().cast<float>();
  t_color_depth_ = frame.T_color_depth.translation().cast<float>();
  values_.create(cam_color.height, cam_color.width, CV_32F);
  values_.setTo(kEmpty);
  cover_.create(cam_color.height, cam_color.width, CV_32F);
  cover_.setTo(kEmpty);
}

void DepthRegistrar::splat(const RgbdFrame& frame, const cv::Rect& depth_roi, bool skip_done) {
  const PinholeCamera& c = cam_color_;
  const float k1 = float(c.dist[0]), k2 = float(c.dist[1]), p1 = float(c.dist[2]),
              p2 = float(c.dist[3]), k3 = float(c.dist[4]);
  const bool distorted = c.hasDistortion();
  const float fx = float(c.fx), fy = float(c.fy), cx = float(c.cx), cy = float(c.cy);
  const float unit = float(frame.depth_unit_m);
  const float u_lim = float(c.width) - 0.5f, v_lim = float(c.height) - 0.5f;
  const float width_f = float(c.width), height_f = float(c.height);
  const Eigen::Matrix3f& R = R_color_depth_;
  const Eigen::Vector3f& t = t_color_depth_;
  const int depth_width = frame.depth.cols;
  for (int v = depth_roi.y; v < depth_roi.y + depth_roi.height; ++v) {
    const std::uint16_t* drow = frame.depth.ptr<std::uint16_t>(v);
    const float* ray = rays_xn_.data() + 2 * (static_cast<size_t>(v) * depth_width + depth_roi.x);
    std::uint8_t* done = skip_done ? splatted_.ptr<std::uint8_t>(v) : nullptr;
    for (int u = depth_roi.x; u < depth_roi.x + depth_roi.width; ++u, ray += 2) {
      if (done) {
        if (done[u]) continue;
        done[u] = 1;
      }
      if (drow[u] == 0) continue;
      const float z = drow[u] * unit;
      const Eigen::Vector3f p = R * Eigen::Vector3f(ray[0] * z, ray[1] * z, z) + t;
      if (p.z() <= 0.0f) continue;
      const float inv_z = 1.0f / p.z();
      float x = p.x() * inv_z, y = p.y() * inv_z;
      if (distorted) {
        const float r2 = x * x + y * y;
        if (r2 > max_radius2_) continue;
        const float radial = 1.0f + r2 * (k1 + r2 * (k2 + r2 * k3));
        const float xd = x * radial + 2.0f * p1 * x * y + p2 * (r2 + 2.0f * x * x);
        y = y * radial + p1 * (r2 + 2.0f * y * y) + 2.0f * p2 * x * y;
        x = xd;
      }
      const float uc = fx * x + cx, vc = fy * y + cy;
      if (!(uc > -1.0f && uc < width_f && vc > -1.0f && vc < height_f)) continue;
      // Cover: the 2x2 pixels around the sub-pixel position (floor and floor + 1 both ways);
      // uc, vc > -1 so truncation of uc + 1 is the floor.
      const int u0 = static_cast<int>(uc + 1.0f) - 1, v0 = static_cast<int>(vc + 1.0f) - 1;
      if (u0 >= 0 && v0 >= 0 && u0 + 1 < c.width && v0 + 1 < c.height) {
        float* top = cover_.ptr<float>(v0) + u0;
        float* bottom = cover_.ptr<float>(v0 + 1) + u0;
        top[0] = std::min(top[0], p.z());
        top[1] = std::min(top[1], p.z());
        bottom[0] = std::min(bottom[0], p.z());
        bottom[1] = std::min(bottom[1], p.z());
      } else {
        for (int y_px = std::max(v0, 0); y_px <= std::min(v0 + 1, c.height - 1); ++y_px) {
          float* cover_row = cover_.ptr<float>(y_px);
          for (int x_px = std::max(u0, 0); x_px <= std::min(u0 + 1, c.width - 1); ++x_px)
            cover_row[x_px] = std::min(cover_row[x_px], p.z());
        }
      }
      if (uc > -0.5f && uc < u_lim && vc > -0.5f && vc < v_lim) {
        float& cell = values_.at<float>(int(vc + 0.5f), int(uc + 0.5f));
        cell = std::min(cell, p.z());  // z-buffer: the nearer surface wins
      }
    }
  }
}

void DepthRegistrar::resolve(const cv::Rect& rect, cv::Mat& out) const {
  const int w = values_.cols, h = values_.rows;
  const float tol = float(options_.registration_fill_max_relative_diff);
  auto trusted = [&](int u, int v) {
    const float s = values_.at<float>(v, u);
    return s != kEmpty && s <= cover_.at<float>(v, u) * (1.0f + tol);
  };
  // Opposite neighbour pairs: horizontal, vertical and both diagonals (where a row crack crosses
  // a column crack only the diagonals have support).
  static constexpr int kPairs[4][4] = {
      {-1, 0, 1, 0}, {0, -1, 0, 1}, {-1, -1, 1, 1}, {1, -1, -1, 1}};
  for (int v = rect.y; v < rect.y + rect.height; ++v) {
    float* dst = out.ptr<float>(v);
    for (int u = rect.x; u < rect.x + rect.width; ++u) {
      const float c = cover_.at<float>(v, u);
      if (c == kEmpty) {
        dst[u] = 0.0f;  // no depth point within a pixel: leave the hole
        continue;
      }
      if (trusted(u, v)) {
        dst[u] = values_.at<float>(v, u);
        continue;
      }
      float best_diff = -1.0f, best_mean = 0.0f;
      if (u > 0 && v > 0 && u < w - 1 && v < h - 1) {
        for (const auto& p : kPairs) {
          const int ua = u + p[0], va = v + p[1], ub = u + p[2], vb = v + p[3];
          if (!trusted(ua, va) || !trusted(ub, vb)) continue;
          const float a = values_.at<float>(va, ua), b = values_.at<float>(vb, ub);
          const float diff = std::fabs(a - b), mean = 0.5f * (a + b);
          if (diff > tol * std::min(a, b) || mean > c * (1.0f + tol)) continue;
          if (best_diff < 0.0f || diff < best_diff) {
            best_diff = diff;
            best_mean = mean;
          }
        }
      }
      dst[u] = best_diff >= 0.0f ? best_mean : c;
    }
  }
}

cv::Rect DepthRegistrar::depthRoiFor(const cv::Rect& colour_rect, double nearest_range_m,
                                     const RgbdFrame& frame, const PinholeCamera& cam_color) const {
  const cv::Rect whole(0, 0, frame.depth.cols, frame.depth.rows);
  // Rays through the rectangle's corners from the nearest possible range out to infinity
  // project into the depth image as segments along the epipolar lines; their bounding box holds
  // every depth pixel that can land inside (the rectangles are a few pixels wide, so distortion
  // does not bend their edges measurably; the margin below absorbs what it does).
  const double x0 = colour_rect.x - 0.5, y0 = colour_rect.y - 0.5;
  const double x1 = colour_rect.x + colour_rect.width - 0.5,
               y1 = colour_rect.y + colour_rect.height - 0.5;
  const double outline[4][2] = {{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}};
  const Eigen::Isometry3d T_depth_color = frame.T_color_depth.inverse(Eigen::Isometry);
  double umin = 1e30, vmin = 1e30, umax = -1e30, vmax = -1e30;
  for (const auto& q : outline) {
    const Eigen::Vector2d xn = cam_color.pixelToNormalized({q[0], q[1]});
    const Eigen::Vector3d dir = Eigen::Vector3d(xn.x(), xn.y(), 1.0).normalized();
    Eigen::Vector2d near_uv, far_uv;
    // Far end: the direction alone (a point at infinity); near end: the nearest range.
    if (!frame.cam_depth.project(T_depth_color.linear() * dir, far_uv) ||
        !frame.cam_depth.project(T_depth_color * (nearest_range_m * dir), near_uv))
      return whole;  // a ray leaves the depth camera's front half-space: no useful bound
    for (const Eigen::Vector2d& p : {near_uv, far_uv}) {
      umin = std::min(umin, p.x());
      umax = std::max(umax, p.x());
      vmin = std::min(vmin, p.y());
      vmax = std::max(vmax, p.y());
    }
  }
  // Two depth pixels of margin for the curvature of distorted epipolar curves.
  constexpr double kMarginPx = 2.0;
  if (!(umax - umin < 4.0 * whole.width && vmax - vmin < 4.0 * whole.height)) return whole;
  const cv::Rect roi(
      cv::Point(int(std::floor(umin - kMarginPx)), int(std::floor(vmin - kMarginPx))),
      cv::Point(int(std::ceil(umax + kMarginPx)) + 1, int(std::ceil(vmax + kMarginPx)) + 1));
  return roi & whole;
}

cv::Mat DepthRegistrar::registerDepth(const RgbdFrame& frame, const PinholeCamera& cam_color) {
  prepare(frame, cam_color);
  cv::Mat out;
  if (frame.depth_aligned_to_color) {
    frame.depth.convertTo(out, CV_32F, frame.depth_unit_m);
    return out;
  }
  const cv::Rect all(0, 0, cam_color.width, cam_color.height);
  splat(frame, cv::Rect(0, 0, frame.depth.cols, frame.depth.rows));
  out.create(cam_color.height, cam_color.width, CV_32F);
  resolve(all, out);
  return out;
}

void DepthRegistrar::registerDepthAround(const RgbdFrame& frame, const PinholeCamera& cam_color,
                                         const std::vector<Eigen::Vector2d>& centres, int radius_px,
                                         cv::Mat& out) {
  prepare(frame, cam_color);
  out.create(cam_color.height, cam_color.width, CV_32F);
  out.setTo(0.0f);
  if (!frame.depth_aligned_to_color) {
    const std::uint16_t lowest = smallestDepthValue(frame.depth);
    any_depth_ = lowest != 0;
    // No depth point is nearer to the colour camera than this (triangle inequality).
    nearest_range_m_ =
        any_depth_
            ? std::max(0.0, lowest * frame.depth_unit_m - frame.T_color_depth.translation().norm())
            : 0.0;
    if (any_depth_ && !(nearest_range_m_ > 0.0))
      splat(frame, cv::Rect(0, 0, frame.depth.cols, frame.depth.rows));
    splatted_.create(frame.depth.rows, frame.depth.cols, CV_8U);
    splatted_.setTo(0);
  }
  registerWindows(frame, cam_color, centres, radius_px, out);
}

void DepthRegistrar::registerMoreDepthAround(const RgbdFrame& frame, const PinholeCamera& cam_color,
                                             const std::vector<Eigen::Vector2d>& centres,
                                             int radius_px, cv::Mat& out) {
  if (out.type() != CV_32FC1 || out.cols != cam_color.width || out.rows != cam_color.height)
    throw std::invalid_argument(
        "registerMoreDepthAround: `out` is not the result of registerDepthAround");
  registerWindows(frame, cam_color, centres, radius_px, out);
}

void DepthRegistrar::registerWindows(const RgbdFrame& frame, const PinholeCamera& cam_color,
                                     const std::vector<Eigen::Vector2d>& centres, int radius_px,
                                     cv::Mat& out) {
  if (radius_px < 0)
    throw std::invalid_argument("registerDepthAround: negative radius " +
                                std::to_string(radius_px));
  const cv::Rect all(0, 0, cam_color.width, cam_color.height);
  if (frame.depth_aligned_to_color) {
    for (const Eigen::Vector2d& c : centres) {
      const cv::Rect r = aroundPixel(c, radius_px) & all;
      if (!r.empty()) frame.depth(r).convertTo(out(r), CV_32F, frame.depth_unit_m);
    }
    return;
  }
  if (!any_depth_) return;
  if (nearest_range_m_ > 0.0) {
    // A pixel's result depends on values and covers one pixel away (pairs of neighbours), and
    // those on the points landing within one pixel of them: three pixels with a safety pixel.
    // (Without a bound the whole image was projected once by registerDepthAround.)
    for (const Eigen::Vector2d& c : centres) {
      const cv::Rect colour = grown(aroundPixel(c, radius_px), 3) & all;
      if (!colour.empty())
        splat(frame, depthRoiFor(colour, nearest_range_m_, frame, cam_color), true);
    }
  }
  for (const Eigen::Vector2d& c : centres) {
    const cv::Rect r = aroundPixel(c, radius_px) & all;
    if (!r.empty()) resolve(r, out);
  }
}

cv::Mat registerDepthToColor(const RgbdFrame& frame, const FrontendOptions& options) {
  DepthRegistrar registrar(options);
  return registrar.registerDepth(frame, frame.cam_color);
}

}  // namespace rgbdi::frontend
