#include "rgbdi/common/camera.h"

namespace rgbdi {

bool PinholeCamera::hasDistortion() const {
  for (double d : dist)
    if (d != 0.0) return true;
  return false;
}

Eigen::Vector2d PinholeCamera::distortNormalized(const Eigen::Vector2d& xn) const {
  if (!hasDistortion()) return xn;
  const double k1 = dist[0], k2 = dist[1], p1 = dist[2], p2 = dist[3], k3 = dist[4];
  const double x = xn.x(), y = xn.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  return {x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
          y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y};
}

Eigen::Vector2d PinholeCamera::undistortNormalized(const Eigen::Vector2d& xd) const {
  if (!hasDistortion()) return xd;
  // Fixed-point iteration x <- x - (distort(x) - xd); converges quickly for the mild distortion
  // of RGB-D cameras.
  Eigen::Vector2d x = xd;
  for (int i = 0; i < 30; ++i) {
    const Eigen::Vector2d err = distortNormalized(x) - xd;
    x -= err;
    if (err.squaredNorm() < 1e-26) break;
  }
  return x;
}

bool PinholeCamera::project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& uv) const {
  if (p_cam.z() <= 1e-9) return false;
  const Eigen::Vector2d xd = distortNormalized(p_cam.head<2>() / p_cam.z());
  uv = {fx * xd.x() + cx, fy * xd.y() + cy};
  return true;
}

Eigen::Vector2d PinholeCamera::pixelToNormalized(const Eigen::Vector2d& uv) const {
  return undistortNormalized({(uv.x() - cx) / fx, (uv.y() - cy) / fy});
}

Eigen::Vector3d PinholeCamera::backProject(const Eigen::Vector2d& uv, double z) const {
  const Eigen::Vector2d xn = pixelToNormalized(uv);
  return {xn.x() * z, xn.y() * z, z};
}

}  // namespace rgbdi
