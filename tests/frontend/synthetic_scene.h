// Test helpers of the front-end tests: procedural textures and a small ray caster that renders
// textured rectangles (planes, box faces, moving patches) into grey, depth and surface-id images
// with exact per-pixel truth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/types.h"

namespace rgbdi::test {

/// Random rectangles of random grey levels, blurred so that bilinear resampling is faithful
/// (KLT sub-pixel accuracy is only meaningful on band-limited images). CV_32FC1 in [0, 255].
inline cv::Mat randomRectangleTexture(int width, int height, std::uint64_t seed,
                                      int rectangles = 600, double blur_sigma = 1.2) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> grey(20.0f, 235.0f);
  std::uniform_int_distribution<int> x(0, width - 1), y(0, height - 1), side(4, 48);
  cv::Mat tex(height, width, CV_32FC1, cv::Scalar(128));
  for (int i = 0; i < rectangles; ++i) {
    const cv::Rect r(x(rng), y(rng), side(rng), side(rng));
    tex(r & cv::Rect(0, 0, width, height)).setTo(grey(rng));
  }
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), blur_sigma);
  return tex;
}

inline cv::Mat toGrey8(const cv::Mat& f) {
  cv::Mat g;
  f.convertTo(g, CV_8UC1);
  return g;
}

/// An RGB frame (R = G = B = grey) with the given stamp and index; no depth.
inline RgbdFrame colourFrame(const cv::Mat& grey8, double t, std::uint64_t index,
                             const PinholeCamera& cam) {
  RgbdFrame f;
  f.t = t;
  f.index = index;
  cv::cvtColor(grey8, f.rgb, cv::COLOR_GRAY2RGB);
  f.cam_color = cam;
  f.source_label = "synthetic frame " + std::to_string(index);
  return f;
}

inline PinholeCamera simpleCamera(double f = 500.0) {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = f;
  c.cx = 319.5;
  c.cy = 239.5;
  return c;
}

/// A textured parallelogram origin + a*u + b*v, a, b in [0, 1]; the texture spans it with
/// `texel_m` metres per texel starting at texel (0, 0).
struct TexturedRect {
  Eigen::Vector3d origin, u, v;
  int texture = -1;  ///< index into Scene::textures, -1 = constant grey 128
  double texel_m = 0.002;
};

struct Scene {
  std::vector<TexturedRect> rects;
  std::vector<cv::Mat> textures;  ///< CV_32FC1

  /// Adds the six faces of an axis-aligned box [lo, hi]; returns the index of its first face.
  int addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int texture) {
    const int first = static_cast<int>(rects.size());
    const Eigen::Vector3d d = hi - lo;
    const Eigen::Vector3d ex(d.x(), 0, 0), ey(0, d.y(), 0), ez(0, 0, d.z());
    rects.push_back({lo, ex, ey, texture});       // z = lo.z
    rects.push_back({lo + ez, ex, ey, texture});  // z = hi.z
    rects.push_back({lo, ey, ez, texture});       // x = lo.x
    rects.push_back({lo + ex, ey, ez, texture});  // x = hi.x
    rects.push_back({lo, ex, ez, texture});       // y = lo.y
    rects.push_back({lo + ey, ex, ez, texture});  // y = hi.y
    return first;
  }
};

/// Ray casting of `scene` into camera `cam` whose optical frame has pose T_world_cam.
/// Outputs (any may be null): grey CV_32FC1, depth z along the optical axis CV_64FC1 (0 = no
/// hit), surface index CV_32SC1 (-1 = none).
struct RenderOutput {
  cv::Mat grey, depth, surface;
};

inline float sampleTexture(const cv::Mat& tex, double x, double y) {
  x = std::clamp(x, 0.0, tex.cols - 1.001);
  y = std::clamp(y, 0.0, tex.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const float a = static_cast<float>(x - x0), b = static_cast<float>(y - y0);
  const float* r0 = tex.ptr<float>(y0);
  const float* r1 = tex.ptr<float>(y0 + 1);
  return (1 - b) * ((1 - a) * r0[x0] + a * r0[x0 + 1]) + b * ((1 - a) * r1[x0] + a * r1[x0 + 1]);
}

inline RenderOutput render(const Scene& scene, const PinholeCamera& cam,
                           const Eigen::Isometry3d& T_world_cam) {
  RenderOutput out;
  out.grey = cv::Mat(cam.height, cam.width, CV_32FC1, cv::Scalar(0));
  out.depth = cv::Mat(cam.height, cam.width, CV_64FC1, cv::Scalar(0));
  out.surface = cv::Mat(cam.height, cam.width, CV_32SC1, cv::Scalar(-1));
  const Eigen::Matrix3d R = T_world_cam.rotation();
  const Eigen::Vector3d c = T_world_cam.translation();
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const Eigen::Vector2d xn = cam.pixelToNormalized({double(u), double(v)});
      const Eigen::Vector3d ray_cam(xn.x(), xn.y(), 1.0);  // z = 1: lambda is the depth
      const Eigen::Vector3d d = R * ray_cam;
      double best = std::numeric_limits<double>::infinity();
      int best_i = -1;
      double best_a = 0, best_b = 0;
      for (size_t i = 0; i < scene.rects.size(); ++i) {
        const TexturedRect& r = scene.rects[i];
        const Eigen::Vector3d n = r.u.cross(r.v);
        const double den = n.dot(d);
        if (std::abs(den) < 1e-12) continue;
        const double lambda = n.dot(r.origin - c) / den;
        if (lambda <= 1e-6 || lambda >= best) continue;
        const Eigen::Vector3d q = c + lambda * d - r.origin;
        const double a = q.dot(r.u) / r.u.squaredNorm(), b = q.dot(r.v) / r.v.squaredNorm();
        if (a < 0 || a > 1 || b < 0 || b > 1) continue;
        best = lambda;
        best_i = static_cast<int>(i);
        best_a = a;
        best_b = b;
      }
      if (best_i < 0) continue;
      const TexturedRect& r = scene.rects[static_cast<size_t>(best_i)];
      out.depth.at<double>(v, u) = best;
      out.surface.at<int>(v, u) = best_i;
      out.grey.at<float>(v, u) =
          r.texture < 0
              ? 128.0f
              : sampleTexture(scene.textures[static_cast<size_t>(r.texture)],
                              best_a * r.u.norm() / r.texel_m, best_b * r.v.norm() / r.texel_m);
    }
  return out;
}

/// True when every pixel in the (2 r + 1)^2 window around (u, v) shows the same surface.
inline bool uniformSurface(const cv::Mat& surface, int u, int v, int r) {
  if (u - r < 0 || v - r < 0 || u + r >= surface.cols || v + r >= surface.rows) return false;
  const int s = surface.at<int>(v, u);
  if (s < 0) return false;
  for (int y = v - r; y <= v + r; ++y)
    for (int x = u - r; x <= u + r; ++x)
      if (surface.at<int>(y, x) != s) return false;
  return true;
}

}  // namespace rgbdi::test
