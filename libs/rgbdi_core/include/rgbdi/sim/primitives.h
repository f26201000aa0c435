// Geometric primitives of the simulated world and their exact ray intersections.
//
// Every primitive is a closed convex solid whose faces carry their own material id, so that a
// ray may start outside (it hits the entry face) or inside (it hits the exit face, e.g. a room
// seen from within). Intersections are split in two steps: intersect() finds only the distance
// and the face (cheap, called many times during BVH traversal); surface() evaluates normal and
// texture coordinates once for the closest hit.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>

namespace rgbdi::sim {

/// Index into Scene's material table (one per surface, so textures differ per surface).
using MaterialId = std::uint32_t;

/// Hits closer than this along the ray are ignored, so a ray starting exactly on a surface does
/// not hit that surface again [m].
constexpr double kMinHitDistance = 1e-9;

/// Distance and face of a ray-primitive intersection (dir is a unit vector, so t is in metres).
struct PrimitiveHit {
  double t = 0.0;
  int face = -1;
};

/// Surface attributes at a hit point.
struct SurfaceInfo {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< outward unit normal of the face
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();      ///< texture coordinates on the face [m]
};

/// Oriented box: local frame at the centre, faces at +-half_extents.
/// Faces: 0 -x, 1 +x, 2 -y, 3 +y, 4 -z, 5 +z (of the box frame).
class Box {
 public:
  static constexpr int kFaces = 6;
  Box(const Eigen::Isometry3d& T_world_box, const Eigen::Vector3d& half_extents,
      const std::array<MaterialId, kFaces>& materials);

  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                 PrimitiveHit& hit) const;
  SurfaceInfo surface(const Eigen::Vector3d& p_world, int face) const;
  Eigen::AlignedBox3d bounds() const;
  MaterialId material(int face) const { return materials_[static_cast<std::size_t>(face)]; }

  const Eigen::Isometry3d& T_world_box() const { return T_world_box_; }
  const Eigen::Vector3d& halfExtents() const { return half_; }

 private:
  Eigen::Isometry3d T_world_box_;
  Eigen::Matrix3d R_box_world_;
  Eigen::Vector3d half_;
  std::array<MaterialId, kFaces> materials_;
  bool axis_aligned_;
};

/// Vertical cylinder (axis along world z), e.g. a pillar.
/// Faces: 0 side, 1 bottom (z_min), 2 top (z_max).
class Cylinder {
 public:
  static constexpr int kFaces = 3;
  Cylinder(const Eigen::Vector2d& center_xy, double radius, double z_min, double z_max,
           const std::array<MaterialId, kFaces>& materials);

  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                 PrimitiveHit& hit) const;
  SurfaceInfo surface(const Eigen::Vector3d& p_world, int face) const;
  Eigen::AlignedBox3d bounds() const;
  MaterialId material(int face) const { return materials_[static_cast<std::size_t>(face)]; }

  const Eigen::Vector2d& centerXY() const { return c_; }
  double radius() const { return r_; }
  double zMin() const { return z0_; }
  double zMax() const { return z1_; }

 private:
  Eigen::Vector2d c_;
  double r_, z0_, z1_;
  std::array<MaterialId, kFaces> materials_;
};

/// Triangular prism (wedge, ramp): a triangle in the x-z plane of its local frame, extruded
/// along local y over [-half_width, half_width]. The triangle may be given in either winding.
/// Faces: 0 edge p0-p1, 1 edge p1-p2, 2 edge p2-p0, 3 cap at -y, 4 cap at +y.
class Prism {
 public:
  static constexpr int kFaces = 5;
  Prism(const Eigen::Isometry3d& T_world_prism, const std::array<Eigen::Vector2d, 3>& profile_xz,
        double half_width, const std::array<MaterialId, kFaces>& materials);

  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                 PrimitiveHit& hit) const;
  SurfaceInfo surface(const Eigen::Vector3d& p_world, int face) const;
  Eigen::AlignedBox3d bounds() const;
  MaterialId material(int face) const { return materials_[static_cast<std::size_t>(face)]; }

 private:
  /// Face planes in the world frame: points x inside satisfy normal.dot(x) <= offset.
  std::array<Eigen::Vector3d, kFaces> normal_;
  std::array<double, kFaces> offset_;
  /// Texture frame of each face in the world: uv = ((x - origin).dot(u_axis), (x -
  /// origin).dot(v_axis)).
  std::array<Eigen::Vector3d, kFaces> uv_origin_, u_axis_, v_axis_;
  std::array<Eigen::Vector3d, 6> corners_;
  std::array<MaterialId, kFaces> materials_;
};

}  // namespace rgbdi::sim
