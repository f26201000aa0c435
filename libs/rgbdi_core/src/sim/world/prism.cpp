#include <cmath>
#include <limits>
#include <stdexcept>

#include "rgbdi/sim/primitives.h"
#include "sim/world/ray_interval.h"

namespace rgbdi::sim {

Prism::Prism(const Eigen::Isometry3d& T_world_prism,
             const std::array<Eigen::Vector2d, 3>& profile_xz, double half_width,
             const std::array<MaterialId, kFaces>& materials)
    : materials_(materials) {
  if (!(half_width > 0.0) || !std::isfinite(half_width))
    throw std::invalid_argument("Prism: half width must be positive and finite");
  if (!T_world_prism.matrix().allFinite()) throw std::invalid_argument("Prism: pose is not finite");
  const Eigen::Vector2d e01 = profile_xz[1] - profile_xz[0];
  const Eigen::Vector2d e02 = profile_xz[2] - profile_xz[0];
  const double area2 = e01.x() * e02.y() - e01.y() * e02.x();
  const double scale = std::max(e01.squaredNorm(), e02.squaredNorm());
  if (!std::isfinite(area2) || std::abs(area2) <= 1e-12 * scale || scale == 0.0)
    throw std::invalid_argument("Prism: the profile triangle is degenerate");

  const Eigen::Matrix3d R = T_world_prism.linear();
  const Eigen::Vector3d ex = R.col(0), ey = R.col(1), ez = R.col(2);
  auto toWorld = [&](const Eigen::Vector2d& q, double y) -> Eigen::Vector3d {
    return T_world_prism * Eigen::Vector3d(q.x(), y, q.y());
  };
  const Eigen::Vector2d centroid = (profile_xz[0] + profile_xz[1] + profile_xz[2]) / 3.0;

  // Side faces: the plane through each triangle edge, extruded along y; outward normal is the
  // in-plane edge normal pointing away from the centroid (works for either winding).
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d a = profile_xz[static_cast<std::size_t>(i)];
    const Eigen::Vector2d b = profile_xz[static_cast<std::size_t>((i + 1) % 3)];
    const Eigen::Vector2d edge = (b - a).normalized();
    Eigen::Vector2d n2(edge.y(), -edge.x());
    if (n2.dot(centroid - a) > 0.0) n2 = -n2;
    const std::size_t f = static_cast<std::size_t>(i);
    normal_[f] = n2.x() * ex + n2.y() * ez;
    const Eigen::Vector3d a_world = toWorld(a, -half_width);
    offset_[f] = normal_[f].dot(a_world);
    uv_origin_[f] = a_world;
    // u along the edge, v across the width: a ramp's texture then runs up the slope.
    u_axis_[f] = edge.x() * ex + edge.y() * ez;
    v_axis_[f] = ey;
  }
  for (int k = 0; k < 2; ++k) {
    const std::size_t f = static_cast<std::size_t>(3 + k);
    const double y = (k == 0) ? -half_width : half_width;
    normal_[f] = (k == 0) ? -ey : ey;
    offset_[f] = normal_[f].dot(toWorld(centroid, y));
    uv_origin_[f] = toWorld(Eigen::Vector2d::Zero(), y);
    u_axis_[f] = ex;
    v_axis_[f] = ez;
  }
  for (int k = 0; k < 6; ++k)
    corners_[static_cast<std::size_t>(k)] =
        toWorld(profile_xz[static_cast<std::size_t>(k % 3)], k < 3 ? -half_width : half_width);
}

bool Prism::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                      PrimitiveHit& hit) const {
  // Convex solid = intersection of half-spaces n.x <= d: clip the ray parameter interval
  // against each plane (entering where n.dir < 0, leaving where n.dir > 0).
  RayInterval in;
  for (int f = 0; f < kFaces; ++f) {
    const std::size_t i = static_cast<std::size_t>(f);
    const double denom = normal_[i].dot(dir);
    const double dist = offset_[i] - normal_[i].dot(origin);  // >= 0 when origin is inside
    if (denom == 0.0) {
      if (dist < 0.0) return false;
      continue;
    }
    const double t = dist / denom;
    if (denom < 0.0) {
      in.clipEntry(t, f);
    } else {
      in.clipExit(t, f);
    }
    if (in.empty()) return false;
  }
  return in.visibleHit(t_max, hit);
}

SurfaceInfo Prism::surface(const Eigen::Vector3d& p_world, int face) const {
  const std::size_t f = static_cast<std::size_t>(face);
  SurfaceInfo s;
  s.normal = normal_[f];
  const Eigen::Vector3d r = p_world - uv_origin_[f];
  s.uv = {r.dot(u_axis_[f]), r.dot(v_axis_[f])};
  return s;
}

Eigen::AlignedBox3d Prism::bounds() const {
  Eigen::AlignedBox3d b;
  for (const Eigen::Vector3d& c : corners_) b.extend(c);
  return b;
}

}  // namespace rgbdi::sim
