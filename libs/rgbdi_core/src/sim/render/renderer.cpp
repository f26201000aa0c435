#include "rgbdi/sim/renderer.h"

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

namespace rgbdi::sim {
namespace {

// Below this |cos(incidence)| the footprint is clamped; such grazing pixels already sample the
// coarsest mip levels.
constexpr double kMinFootprintCos = 1e-3;

Eigen::Vector3d unitRay(const PinholeCamera& cam, double u, double v) {
  const Eigen::Vector2d xn = cam.pixelToNormalized({u, v});
  return Eigen::Vector3d(xn.x(), xn.y(), 1.0).normalized();
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
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
  spread_.resize(n);
  for (int v = 0; v < cam.height; ++v)
    for (int u = 0; u < cam.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * static_cast<std::size_t>(cam.width) +
                            static_cast<std::size_t>(u);
      rays_cam_[i] = unitRay(cam, u, v);
      // Angular pixel size from the rays through the pixel's edges (larger of the two axes:
      // blurring a little is harmless, aliasing creates false corners).
      const double ax = angleBetween(unitRay(cam, u - 0.5, v), unitRay(cam, u + 0.5, v));
      const double ay = angleBetween(unitRay(cam, u, v - 0.5), unitRay(cam, u, v + 0.5));
      spread_[i] = static_cast<float>(std::max(ax, ay));
    }
}

void Renderer::render(const Eigen::Isometry3d& T_world_cam, cv::Mat& rgb, cv::Mat& depth) const {
  rgb.create(cam_.height, cam_.width, CV_8UC3);
  depth.create(cam_.height, cam_.width, CV_32FC1);
  const Eigen::Matrix3d R = T_world_cam.linear();
  const Eigen::Vector3d origin = T_world_cam.translation();
  const Eigen::Vector3d light = opt_.light_dir_world.normalized();
  const double lod_scale = std::exp2(opt_.lod_bias);
  Hit hit;
  std::size_t i = 0;
  for (int v = 0; v < cam_.height; ++v) {
    std::uint8_t* out = rgb.ptr<std::uint8_t>(v);
    float* dout = depth.ptr<float>(v);
    for (int u = 0; u < cam_.width; ++u, ++i) {
      const Eigen::Vector3d dir = R * rays_cam_[i];
      if (!scene_.raycast(origin, dir, opt_.max_range_m, hit)) {
        out[3 * u] = opt_.background[0];
        out[3 * u + 1] = opt_.background[1];
        out[3 * u + 2] = opt_.background[2];
        dout[u] = 0.0f;
        continue;
      }
      dout[u] = static_cast<float>(hit.t * rays_cam_[i].z());
      const double cos_inc = std::max(std::abs(hit.normal.dot(dir)), kMinFootprintCos);
      const double footprint = hit.t * spread_[i] / cos_inc * lod_scale;
      const Eigen::Vector3f albedo = scene_.surfaceColor(hit.material, hit.uv, footprint);
      // Wrapped Lambert: surfaces facing away from the light keep the ambient level, standing
      // in for light bounced around an indoor scene.
      const double shade = opt_.ambient + opt_.diffuse * (0.5 + 0.5 * hit.normal.dot(light));
      for (int c = 0; c < 3; ++c)
        out[3 * u + c] = cv::saturate_cast<std::uint8_t>(albedo[c] * static_cast<float>(shade));
    }
  }
  if (opt_.optics_blur_sigma_px > 0.0)
    cv::GaussianBlur(rgb, rgb, cv::Size(0, 0), opt_.optics_blur_sigma_px, 0.0, cv::BORDER_REPLICATE);
}

}  // namespace rgbdi::sim
