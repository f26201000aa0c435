#include "rgbdi/frontend/depth_registration.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rgbdi::frontend {
namespace {

bool sameCamera(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.dist == b.dist;
}

[[noreturn]] void fail(const RgbdFrame& frame, const std::string& what) {
  const std::string where = frame.source_label.empty()
                                ? "frame " + std::to_string(frame.index)
                                : frame.source_label;
  throw std::invalid_argument("depth registration: " + where + ": " + what);
}

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

/// Radial-tangential distortion in float (the splat loop runs it for every depth pixel).
struct FloatDistortion {
  float k1, k2, p1, p2, k3;
  bool any;
  explicit FloatDistortion(const PinholeCamera& c)
      : k1(float(c.dist[0])), k2(float(c.dist[1])), p1(float(c.dist[2])), p2(float(c.dist[3])),
        k3(float(c.dist[4])), any(c.hasDistortion()) {}
  void apply(float& x, float& y, float r2) const {
    const float radial = 1.0f + r2 * (k1 + r2 * (k2 + r2 * k3));
    const float xd = x * radial + 2.0f * p1 * x * y + p2 * (r2 + 2.0f * x * x);
    const float yd = y * radial + p1 * (r2 + 2.0f * y * y) + 2.0f * p2 * x * y;
    x = xd;
    y = yd;
  }
};

/// Largest squared normalised radius worth projecting: the polynomial distortion model is only
/// meaningful inside the field of view it was calibrated on and can fold far-away points back
/// into the image. The bound is the image border's radius with a margin of half again.
float maxNormalisedRadius2(const PinholeCamera& cam) {
  double r2 = 0.0;
  const double w = cam.width - 1, h = cam.height - 1;
  const double border[8][2] = {{0, 0}, {w, 0}, {0, h}, {w, h}, {w / 2, 0}, {w / 2, h}, {0, h / 2}, {w, h / 2}};
  for (const auto& p : border) r2 = std::max(r2, cam.pixelToNormalized({p[0], p[1]}).squaredNorm());
  return static_cast<float>(1.5 * r2);
}

/// Combines the nearest-pixel values and the 2x2 cover (see DepthRegistrar docs).
cv::Mat resolveCracksAndOcclusions(const cv::Mat& values, const cv::Mat& cover, float tol) {
  const int w = values.cols, h = values.rows;
  auto trusted = [&](int u, int v) {
    const float s = values.at<float>(v, u);
    return s > 0.0f && s <= cover.at<float>(v, u) * (1.0f + tol);
  };
  cv::Mat out(values.size(), CV_32F, cv::Scalar(0));
  for (int v = 0; v < h; ++v) {
    const float* cover_row = cover.ptr<float>(v);
    float* dst = out.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const float c = cover_row[u];
      if (c <= 0.0f) continue;  // no depth point within a pixel: leave the hole
      if (trusted(u, v)) {
        dst[u] = values.at<float>(v, u);
        continue;
      }
      if (u == 0 || v == 0 || u == w - 1 || v == h - 1) {
        dst[u] = c;
        continue;
      }
      // Opposite neighbour pairs: horizontal, vertical and both diagonals (where a row crack
      // crosses a column crack only the diagonals have support).
      static constexpr int kPairs[4][4] = {{-1, 0, 1, 0}, {0, -1, 0, 1}, {-1, -1, 1, 1}, {1, -1, -1, 1}};
      float best_diff = -1.0f, best_mean = 0.0f;
      for (const auto& p : kPairs) {
        const int ua = u + p[0], va = v + p[1], ub = u + p[2], vb = v + p[3];
        if (!trusted(ua, va) || !trusted(ub, vb)) continue;
        const float a = values.at<float>(va, ua), b = values.at<float>(vb, ub);
        const float diff = std::fabs(a - b);
        const float mean = 0.5f * (a + b);
        if (diff > tol * std::min(a, b) || mean > c * (1.0f + tol)) continue;
        if (best_diff < 0.0f || diff < best_diff) {
          best_diff = diff;
          best_mean = mean;
        }
      }
      dst[u] = best_diff >= 0.0f ? best_mean : c;
    }
  }
  return out;
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

cv::Mat DepthRegistrar::registerDepth(const RgbdFrame& frame, const PinholeCamera& cam_color) {
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
    cv::Mat out;
    frame.depth.convertTo(out, CV_32F, frame.depth_unit_m);
    return out;
  }

  const PinholeCamera& cam_depth = frame.cam_depth;
  if (!cam_depth.valid()) fail(frame, "depth is not aligned to colour but has no valid depth intrinsics");
  if (frame.depth.cols != cam_depth.width || frame.depth.rows != cam_depth.height)
    fail(frame, "depth image is " + sizeText(frame.depth.cols, frame.depth.rows) +
                    " but the depth camera is " + sizeText(cam_depth.width, cam_depth.height));
  if (!frame.T_color_depth.matrix().allFinite()) fail(frame, "T_color_depth is not finite");
  updateRays(cam_depth);

  const Eigen::Matrix3f R = frame.T_color_depth.rotation().cast<float>();
  const Eigen::Vector3f t = frame.T_color_depth.translation().cast<float>();
  const FloatDistortion distortion(cam_color);
  const float r2_max = maxNormalisedRadius2(cam_color);
  const float fx = float(cam_color.fx), fy = float(cam_color.fy);
  const float cx = float(cam_color.cx), cy = float(cam_color.cy);
  const float unit = float(frame.depth_unit_m);
  const float u_lim = float(cam_color.width) - 0.5f, v_lim = float(cam_color.height) - 0.5f;

  const int w = cam_color.width, h = cam_color.height;
  cv::Mat values(h, w, CV_32F, cv::Scalar(0)), cover(h, w, CV_32F, cv::Scalar(0));
  auto keepNearer = [](float& cell, float z) {
    if (cell == 0.0f || z < cell) cell = z;
  };
  const float* ray = rays_xn_.data();
  for (int v = 0; v < frame.depth.rows; ++v) {
    const std::uint16_t* drow = frame.depth.ptr<std::uint16_t>(v);
    for (int u = 0; u < frame.depth.cols; ++u, ray += 2) {
      if (drow[u] == 0) continue;
      const float z = drow[u] * unit;
      const Eigen::Vector3f p = R * Eigen::Vector3f(ray[0] * z, ray[1] * z, z) + t;
      if (p.z() <= 0.0f) continue;
      float x = p.x() / p.z(), y = p.y() / p.z();
      if (distortion.any) {
        const float r2 = x * x + y * y;
        if (r2 > r2_max) continue;
        distortion.apply(x, y, r2);
      }
      const float uc = fx * x + cx, vc = fy * y + cy;
      if (!(uc > -1.0f && uc < float(w) && vc > -1.0f && vc < float(h))) continue;
      // 2x2 cover: the pixels at floor() and floor() + 1 in both directions.
      const int u0 = static_cast<int>(std::floor(uc)), v0 = static_cast<int>(std::floor(vc));
      for (int dv = 0; dv <= 1; ++dv) {
        const int y_px = v0 + dv;
        if (y_px < 0 || y_px >= h) continue;
        float* cover_row = cover.ptr<float>(y_px);
        for (int du = 0; du <= 1; ++du) {
          const int x_px = u0 + du;
          if (x_px >= 0 && x_px < w) keepNearer(cover_row[x_px], p.z());
        }
      }
      if (uc > -0.5f && uc < u_lim && vc > -0.5f && vc < v_lim)
        keepNearer(values.at<float>(int(vc + 0.5f), int(uc + 0.5f)), p.z());
    }
  }
  return resolveCracksAndOcclusions(values, cover, float(options_.registration_fill_max_relative_diff));
}

cv::Mat registerDepthToColor(const RgbdFrame& frame, const FrontendOptions& options) {
  DepthRegistrar registrar(options);
  return registrar.registerDepth(frame, frame.cam_color);
}

}  // namespace rgbdi::frontend
