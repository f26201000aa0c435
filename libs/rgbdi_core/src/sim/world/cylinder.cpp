#include <cmath>
#include <limits>
#include <stdexcept>

#include "rgbdi/sim/primitives.h"
#include "sim/world/ray_interval.h"

namespace rgbdi::sim {

Cylinder::Cylinder(const Eigen::Vector2d& center_xy, double radius, double z_min, double z_max,
                   const std::array<MaterialId, kFaces>& materials)
    : c_(center_xy), r_(radius), z0_(z_min), z1_(z_max), materials_(materials) {
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw std::invalid_argument("Cylinder: radius must be positive and finite");
  if (!(z_max > z_min) || !std::isfinite(z_min) || !std::isfinite(z_max))
    throw std::invalid_argument("Cylinder: need finite z_min < z_max");
  if (!center_xy.allFinite()) throw std::invalid_argument("Cylinder: centre is not finite");
}

bool Cylinder::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                         PrimitiveHit& hit) const {
  // The solid is the intersection of an infinite vertical cylinder and the slab z0..z1:
  // intersect both parameter intervals and remember which surface bounds each end.
  RayInterval in;

  const double ox = origin.x() - c_.x(), oy = origin.y() - c_.y();
  const double a = dir.x() * dir.x() + dir.y() * dir.y();
  const double c = ox * ox + oy * oy - r_ * r_;
  if (a == 0.0) {
    if (c > 0.0) return false;  // vertical ray outside the circle
  } else {
    const double b = ox * dir.x() + oy * dir.y();  // half of the linear coefficient
    const double disc = b * b - a * c;
    if (disc < 0.0) return false;
    const double sq = std::sqrt(disc);
    // Numerically stable roots of a t^2 + 2 b t + c.
    const double q = (b >= 0.0) ? -(b + sq) : (-b + sq);
    double t0 = q / a, t1 = (q != 0.0) ? c / q : t0;
    if (t0 > t1) std::swap(t0, t1);
    in.clipEntry(t0, 0);
    in.clipExit(t1, 0);
  }

  if (dir.z() == 0.0) {
    if (origin.z() < z0_ || origin.z() > z1_) return false;
  } else {
    const double inv = 1.0 / dir.z();
    double tb = (z0_ - origin.z()) * inv, tt = (z1_ - origin.z()) * inv;
    int fb = 1, ft = 2;
    if (tb > tt) {
      std::swap(tb, tt);
      std::swap(fb, ft);
    }
    in.clipEntry(tb, fb);
    in.clipExit(tt, ft);
  }
  return in.visibleHit(t_max, hit);
}

SurfaceInfo Cylinder::surface(const Eigen::Vector3d& p_world, int face) const {
  SurfaceInfo s;
  const double x = p_world.x() - c_.x(), y = p_world.y() - c_.y();
  if (face == 0) {
    const double n = std::hypot(x, y);
    s.normal = n > 0.0 ? Eigen::Vector3d(x / n, y / n, 0.0) : Eigen::Vector3d::UnitX();
    // Arc length around the axis keeps texels square on the curved side.
    s.uv = {(std::atan2(y, x) + M_PI) * r_, p_world.z() - z0_};
  } else {
    s.normal = Eigen::Vector3d(0.0, 0.0, face == 1 ? -1.0 : 1.0);
    s.uv = {x + r_, y + r_};
  }
  return s;
}

Eigen::AlignedBox3d Cylinder::bounds() const {
  return {Eigen::Vector3d(c_.x() - r_, c_.y() - r_, z0_),
          Eigen::Vector3d(c_.x() + r_, c_.y() + r_, z1_)};
}

}  // namespace rgbdi::sim
