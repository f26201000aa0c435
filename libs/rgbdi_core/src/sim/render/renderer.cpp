#include "rgbdi/sim/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace rgbdi::sim {
namespace {

// Below this |cos(incidence)| the footprint is clamped; such grazing pixels already sample the
// coarsest mip levels.
constexpr double kMinFootprintCos = 1e-3;
// Tile edge [px]: large enough to amortise culling, small enough to keep candidate lists short.
constexpr int kTileSize = 16;
// Slack of the frustum-box test [m], so rounding never culls a primitive a ray could hit.
constexpr double kCullSlack = 1e-9;

Eigen::Vector3d unitRay(const PinholeCamera& cam, double u, double v) {
  const Eigen::Vector2d xn = cam.pixelToNormalized({u, v});
  return Eigen::Vector3d(xn.x(), xn.y(), 1.0).normalized();
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Margin of the per-pixel bounds test in normalised image coordinates (float rounding).
constexpr float kRectSlack = 1e-5f;

struct Candidate {
  double near;  ///< distance from the camera centre to the primitive's bounds [m]
  std::uint32_t prim;
  /// Bounds of the primitive's projection in undistorted normalised coordinates (x/z, y/z);
  /// unbounded when part of its box is not in front of the camera.
  float x_min, x_max, y_min, y_max;
};

// Rectangle covering the central projection of a box: the projection of a convex solid lying in
// front of the camera is the convex hull of its projected corners.
void projectBounds(const Eigen::AlignedBox3d& b, const Eigen::Matrix3d& R_cam_world,
                   const Eigen::Vector3d& origin, Candidate& c) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner(k & 1 ? b.max().x() : b.min().x(),
                                 k & 2 ? b.max().y() : b.min().y(),
                                 k & 4 ? b.max().z() : b.min().z());
    const Eigen::Vector3d p = R_cam_world * (corner - origin);
    if (!(p.z() > 1e-6)) {
      c.x_min = c.y_min = -kInf;
      c.x_max = c.y_max = kInf;
      return;
    }
    x0 = std::min(x0, p.x() / p.z());
    x1 = std::max(x1, p.x() / p.z());
    y0 = std::min(y0, p.y() / p.z());
    y1 = std::max(y1, p.y() / p.z());
  }
  c.x_min = static_cast<float>(x0) - kRectSlack;
  c.x_max = static_cast<float>(x1) + kRectSlack;
  c.y_min = static_cast<float>(y0) - kRectSlack;
  c.y_max = static_cast<float>(y1) + kRectSlack;
}

// True when the box lies entirely on the positive side of the plane n.(x - o) = 0.
bool outside(const Eigen::Vector3d& n, const Eigen::Vector3d& o, const Eigen::AlignedBox3d& b) {
  double s = 0.0;
  for (int a = 0; a < 3; ++a) s += n[a] * ((n[a] > 0.0 ? b.min()[a] : b.max()[a]) - o[a]);
  return s > kCullSlack;
}

}  // namespace

Renderer::Renderer(const Scene& scene, const PinholeCamera& cam, const RenderOptions& options)
    : scene_(scene), cam_(cam), opt_(options) {
  if (!cam.valid()) throw std::invalid_argument("Renderer: invalid camera (size or focal length)");
  if (!scene.built()) throw std::invalid_argument("Renderer: the scene must be built first");
  if (!(options.max_range_m > 0.0) || options.ambient < 0.0 || options.diffuse < 0.0 ||
      options.optics_blur_sigma_px < 0.0 || !(options.light_dir_world.norm() > 0.0))
    throw std::invalid_argument("Renderer: invalid render options");
  const std::size_t n = static_cast<std::size_t>(cam.width) * static_cast<std::size_t>(cam.height);
  rays_cam_.resize(n);
  normalized_.resize(n);
  spread_.resize(n);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(cam.width) +
                            static_cast<std::size_t>(u);
      rays_cam_[i] = unitRay(cam, u, v);
      normalized_[i] = {static_cast<float>(rays_cam_[i].x() / rays_cam_[i].z()),
                        static_cast<float>(rays_cam_[i].y() / rays_cam_[i].z())};
      // Angular pixel size from the rays through the pixel's edges (larger of the two axes:
      // blurring a little is harmless, aliasing creates false corners).
      const double ax = angleBetween(unitRay(cam, u - 0.5, v), unitRay(cam, u + 0.5, v));
      const double ay = angleBetween(unitRay(cam, u, v - 0.5), unitRay(cam, u, v + 0.5));
      spread_[i] = static_cast<float>(std::max(ax, ay));
    }
  for (int v0 = 0; v0 < cam.height; v0 += kTileSize)
    for (int u0 = 0; u0 < cam.width; u0 += kTileSize) {
      Tile t{u0,
             v0,
             std::min(u0 + kTileSize, cam.width),
             std::min(v0 + kTileSize, cam.height),
             std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity(),
             -std::numeric_limits<double>::infinity()};
      for (int v = t.v0; v < t.v1; ++v)
        for (int u = t.u0; u < t.u1; ++u) {
          const Eigen::Vector3d& r = rays_cam_[static_cast<std::size_t>(v) * cam.width + u];
          const double x = r.x() / r.z(), y = r.y() / r.z();
          t.x_min = std::min(t.x_min, x);
          t.x_max = std::max(t.x_max, x);
          t.y_min = std::min(t.y_min, y);
          t.y_max = std::max(t.y_max, y);
        }
      tiles_.push_back(t);
    }
}

namespace {

// Rays are rotated, not re-normalised: a rotation that is not orthonormal would silently give
// wrong depths.
void checkPose(const Eigen::Isometry3d& T_world_cam, const char* who) {
  constexpr double kRotationTolerance = 1e-6;
  if (!T_world_cam.matrix().allFinite() ||
      !((T_world_cam.linear().transpose() * T_world_cam.linear() - Eigen::Matrix3d::Identity())
            .cwiseAbs()
            .maxCoeff() < kRotationTolerance))
    throw std::invalid_argument(std::string(who) +
                                ": camera pose must be finite with an orthonormal rotation");
}

}  // namespace

void Renderer::render(const Eigen::Isometry3d& T_world_cam, cv::Mat& rgb, cv::Mat& depth) const {
  checkPose(T_world_cam, "Renderer::render");
  rgb.create(cam_.height, cam_.width, CV_8UC3);
  depth.create(cam_.height, cam_.width, CV_32FC1);
  renderRows(T_world_cam, 0, cam_.height, &rgb, &depth);
  blur(rgb);
}

void Renderer::renderRollingShutter(const std::vector<Eigen::Isometry3d>& T_world_cam_rows,
                                    const Eigen::Isometry3d& T_world_cam_depth, cv::Mat& rgb,
                                    cv::Mat& depth) const {
  if (T_world_cam_rows.size() != static_cast<std::size_t>(cam_.height))
    throw std::invalid_argument(
        "Renderer::renderRollingShutter: " + std::to_string(T_world_cam_rows.size()) +
        " row poses for " + std::to_string(cam_.height) + " rows");
  for (const Eigen::Isometry3d& T : T_world_cam_rows)
    checkPose(T, "Renderer::renderRollingShutter");
  checkPose(T_world_cam_depth, "Renderer::renderRollingShutter");
  rgb.create(cam_.height, cam_.width, CV_8UC3);
  depth.create(cam_.height, cam_.width, CV_32FC1);
  renderRows(T_world_cam_depth, 0, cam_.height, nullptr, &depth);
  for (int v = 0; v < cam_.height; ++v)
    renderRows(T_world_cam_rows[static_cast<std::size_t>(v)], v, v + 1, &rgb, nullptr);
  blur(rgb);
}

void Renderer::blur(cv::Mat& rgb) const {
  if (opt_.optics_blur_sigma_px > 0.0)
    cv::GaussianBlur(rgb, rgb, cv::Size(0, 0), opt_.optics_blur_sigma_px, 0.0,
                     cv::BORDER_REPLICATE);
}

void Renderer::renderRows(const Eigen::Isometry3d& T_world_cam, int v_begin, int v_end,
                          cv::Mat* rgb, cv::Mat* depth) const {
  const Eigen::Matrix3d R = T_world_cam.linear();
  const Eigen::Vector3d origin = T_world_cam.translation();
  const Eigen::Vector3d light = opt_.light_dir_world.normalized();
  const double lod_scale = std::exp2(opt_.lod_bias);
  const double max_range = opt_.max_range_m;
  const std::uint32_t prims = static_cast<std::uint32_t>(scene_.primitiveCount());

  // Primitives within range, with their distance from the camera (once per frame).
  std::vector<Candidate> in_range;
  in_range.reserve(prims);
  const Eigen::Matrix3d R_cam_world = R.transpose();
  for (std::uint32_t p = 0; p < prims; ++p) {
    const Eigen::AlignedBox3d& b = scene_.primitiveBounds(p);
    Candidate c{std::sqrt(b.squaredExteriorDistance(origin)), p, 0, 0, 0, 0};
    if (c.near > max_range) continue;
    projectBounds(b, R_cam_world, origin, c);
    in_range.push_back(c);
  }
  // Sorted once, so every tile's list comes out sorted (ties by index, for determinism).
  std::sort(in_range.begin(), in_range.end(), [](const Candidate& a, const Candidate& b) {
    return a.near < b.near || (a.near == b.near && a.prim < b.prim);
  });

  std::vector<Candidate> cand;
  cand.reserve(in_range.size());
  Hit hit;
  std::uint32_t hint = std::numeric_limits<std::uint32_t>::max();
  for (const Tile& tile : tiles_) {
    if (tile.v1 <= v_begin || tile.v0 >= v_end) continue;
    // The tile's frustum: x_min z <= x <= x_max z and y_min z <= y <= y_max z in the camera
    // frame; its four side planes in the world frame all pass through the camera centre.
    const Eigen::Vector3d planes[4] = {
        R * Eigen::Vector3d(-1, 0, tile.x_min), R * Eigen::Vector3d(1, 0, -tile.x_max),
        R * Eigen::Vector3d(0, -1, tile.y_min), R * Eigen::Vector3d(0, 1, -tile.y_max)};
    cand.clear();
    for (const Candidate& c : in_range) {
      const Eigen::AlignedBox3d& b = scene_.primitiveBounds(c.prim);
      if (outside(planes[0], origin, b) || outside(planes[1], origin, b) ||
          outside(planes[2], origin, b) || outside(planes[3], origin, b))
        continue;
      cand.push_back(c);
    }

    for (int v = std::max(tile.v0, v_begin); v < std::min(tile.v1, v_end); ++v) {
      std::uint8_t* out = rgb ? rgb->ptr<std::uint8_t>(v) : nullptr;
      float* dout = depth ? depth->ptr<float>(v) : nullptr;
      for (int u = tile.u0; u < tile.u1; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * cam_.width + u;
        const Eigen::Vector3d dir = R * rays_cam_[i];
        const float xn = normalized_[i].x(), yn = normalized_[i].y();
        // Closest hit: the neighbour's primitive first (usually the answer, giving a tight
        // bound), then candidates in order of distance until they start beyond the best hit.
        PrimitiveHit best, ph;
        std::uint32_t best_prim = 0;
        double t_max = max_range;
        if (hint < prims && scene_.intersectPrimitive(hint, origin, dir, t_max, best)) {
          best_prim = hint;
          t_max = best.t;
        }
        for (const Candidate& c : cand) {
          if (c.near > t_max) break;
          if (c.prim == hint || xn < c.x_min || xn > c.x_max || yn < c.y_min || yn > c.y_max)
            continue;
          if (scene_.intersectPrimitive(c.prim, origin, dir, t_max, ph) &&
              Scene::closerHit(ph, c.prim, best, best_prim)) {
            best = ph;
            best_prim = c.prim;
            t_max = ph.t;
          }
        }
        if (best.face < 0) {
          if (out) {
            out[3 * u] = opt_.background[0];
            out[3 * u + 1] = opt_.background[1];
            out[3 * u + 2] = opt_.background[2];
          }
          if (dout) dout[u] = 0.0f;
          continue;
        }
        hint = best_prim;
        if (dout) dout[u] = static_cast<float>(best.t * rays_cam_[i].z());
        if (!out) continue;
        scene_.completeHit(best_prim, best, origin, dir, hit);
        const double cos_inc = std::max(std::abs(hit.normal.dot(dir)), kMinFootprintCos);
        const double footprint = hit.t * spread_[i] / cos_inc * lod_scale;
        const Eigen::Vector3f albedo = scene_.surfaceColor(hit.material, hit.uv, footprint);
        // Wrapped Lambert: surfaces facing away from the light keep the ambient level,
        // standing in for light bounced around an indoor scene.
        const double shade = opt_.ambient + opt_.diffuse * (0.5 + 0.5 * hit.normal.dot(light));
        for (int c = 0; c < 3; ++c)
          out[3 * u + c] = cv::saturate_cast<std::uint8_t>(albedo[c] * static_cast<float>(shade));
      }
    }
  }
}

}  // namespace rgbdi::sim
