#include <cmath>
#include <limits>
#include <stdexcept>

#include "rgbdi/sim/primitives.h"
#include "sim/world/ray_interval.h"

namespace rgbdi::sim {

Box::Box(const Eigen::Isometry3d& T_world_box, const Eigen::Vector3d& half_extents,
         const std::array<MaterialId, kFaces>& materials)
    : T_world_box_(T_world_box),
      R_box_world_(T_world_box.rotation().transpose()),
      half_(half_extents),
      materials_(materials),
      axis_aligned_(T_world_box.linear() == Eigen::Matrix3d::Identity()) {
  if (!(half_extents.array() > 0.0).all() || !half_extents.allFinite())
    throw std::invalid_argument("Box: half extents must be positive and finite");
  if (!T_world_box.matrix().allFinite()) throw std::invalid_argument("Box: pose is not finite");
}

bool Box::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                    PrimitiveHit& hit) const {
  // Slab test in the box frame. Track which axis bounds the entry and the exit interval so the
  // face is known without a second pass.
  // Axis-aligned boxes (room slabs, most furniture) skip the rotation into the box frame.
  const Eigen::Vector3d o =
      axis_aligned_ ? Eigen::Vector3d(origin - T_world_box_.translation())
                    : Eigen::Vector3d(R_box_world_ * (origin - T_world_box_.translation()));
  const Eigen::Vector3d d = axis_aligned_ ? dir : Eigen::Vector3d(R_box_world_ * dir);
  RayInterval in;
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      // Parallel to this slab: inside it for all t, or never.
      if (std::abs(o[a]) > half_[a]) return false;
      continue;
    }
    const double inv = 1.0 / d[a];
    double t0 = (-half_[a] - o[a]) * inv;  // reaches the -a face
    double t1 = (half_[a] - o[a]) * inv;   // reaches the +a face
    int f0 = 2 * a, f1 = 2 * a + 1;
    if (t0 > t1) {
      std::swap(t0, t1);
      std::swap(f0, f1);
    }
    in.clipEntry(t0, f0);
    in.clipExit(t1, f1);
  }
  return in.visibleHit(t_max, hit);
}

SurfaceInfo Box::surface(const Eigen::Vector3d& p_world, int face) const {
  const int axis = face / 2;
  const double sign = (face % 2 == 0) ? -1.0 : 1.0;
  SurfaceInfo s;
  s.normal = sign * T_world_box_.linear().col(axis);
  // Texture axes are the two other box axes, measured from the face corner so the coordinates
  // are positive metres. Side faces put the box z axis on v, so brick rows and shelves stay
  // level when the box stands upright.
  const Eigen::Vector3d p = R_box_world_ * (p_world - T_world_box_.translation()) + half_;
  if (axis == 0)
    s.uv = {p.y(), p.z()};
  else if (axis == 1)
    s.uv = {p.x(), p.z()};
  else
    s.uv = {p.x(), p.y()};
  return s;
}

Eigen::AlignedBox3d Box::bounds() const {
  const Eigen::Matrix3d A = T_world_box_.linear().cwiseAbs();
  const Eigen::Vector3d r = A * half_;
  return {T_world_box_.translation() - r, T_world_box_.translation() + r};
}

}  // namespace rgbdi::sim
