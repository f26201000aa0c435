// The simulated world: primitives with per-surface materials, a BVH and ray casting.
//
// Build the scene with the add* helpers, call build() once, then raycast() from any number of
// threads (raycast is const and allocation-free). Every face created by a helper gets its own
// material, so every surface shows a different part of the procedural textures.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "rgbdi/sim/bvh.h"
#include "rgbdi/sim/primitives.h"
#include "rgbdi/sim/texture.h"

namespace rgbdi::sim {

/// Closest intersection of a ray with the scene.
struct Hit {
  double t = 0.0;                                    ///< distance along the unit ray [m]
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< world point [m]
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< unit normal facing the ray origin
  MaterialId material = 0;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();  ///< texture coordinates on the surface [m]
  std::uint32_t primitive = 0;                   ///< index in insertion order
  int face = -1;                                 ///< face of that primitive (see primitives.h)
};

/// Textures of the six surfaces of a room (walls in the order -x, +x, -y, +y).
struct RoomStyles {
  TextureStyle floor = TextureStyle::Tiles;
  TextureStyle ceiling = TextureStyle::Speckle;
  std::array<TextureStyle, 4> walls{TextureStyle::Posters, TextureStyle::Bricks,
                                    TextureStyle::Shelves, TextureStyle::Planks};
  /// Perceptual aliasing: the inner face of the +x wall shows the inner face of the -x wall
  /// (same style, seed, offset, orientation and gain) mirrored along y, so that two cameras a
  /// half turn apart about the room's vertical centre line, one facing each wall, see the same
  /// wall image. walls[1] is then unused for that face.
  bool aliased_x_walls = false;
};

class Scene {
 public:
  explicit Scene(std::uint64_t seed = 1, const TextureOptions& texture_options = {});

  /// A new material of the given style with its own seed (derived from the scene seed).
  MaterialId addMaterial(TextureStyle style);
  /// Makes material `target` look like `source` seen mirrored about u = mirror_length_m / 2 on
  /// its face (see mirroredAppearance): it takes the source's style and seed. Other material
  /// ids and appearances are unchanged.
  void aliasMaterialMirrored(MaterialId target, MaterialId source, double mirror_length_m);
  const Material& material(MaterialId id) const;

  // --- primitives (each returns its primitive index; each face gets a fresh material) ---
  std::uint32_t addBox(const Eigen::Isometry3d& T_world_box, const Eigen::Vector3d& half_extents,
                       TextureStyle style);
  std::uint32_t addBox(const Eigen::Isometry3d& T_world_box, const Eigen::Vector3d& half_extents,
                       const std::array<MaterialId, Box::kFaces>& materials);
  /// Vertical pillar from z_min to z_max.
  std::uint32_t addCylinder(const Eigen::Vector2d& center_xy, double radius, double z_min,
                            double z_max, TextureStyle style);
  /// General wedge: triangle profile in the local x-z plane extruded along local y (+-half_width).
  std::uint32_t addPrism(const Eigen::Isometry3d& T_world_prism,
                         const std::array<Eigen::Vector2d, 3>& profile_xz, double half_width,
                         TextureStyle style);
  /// Ramp rising from height base_z at from_xy to base_z + height at to_xy (then a vertical face
  /// down to base_z), width measured horizontally across the direction of travel.
  std::uint32_t addRamp(const Eigen::Vector2d& from_xy, const Eigen::Vector2d& to_xy, double base_z,
                        double width, double height, TextureStyle style);
  /// Symmetric up-down ramp: rises from from_xy to height at the midpoint, descends to to_xy.
  std::uint32_t addSymmetricRamp(const Eigen::Vector2d& from_xy, const Eigen::Vector2d& to_xy,
                                 double base_z, double width, double height, TextureStyle style);
  /// Step (or any object standing on the floor): box of footprint size_xy rotated by yaw [rad]
  /// about z, from base_z to base_z + height.
  std::uint32_t addStep(const Eigen::Vector2d& center_xy, const Eigen::Vector2d& size_xy,
                        double yaw, double base_z, double height, TextureStyle style);
  /// Closed room whose interior is exactly [min_corner, max_corner]: floor, ceiling and four
  /// walls as slabs of the given thickness outside the interior. Returns the six primitive
  /// indices (floor, ceiling, walls -x, +x, -y, +y).
  std::array<std::uint32_t, 6> addRoom(const Eigen::Vector3d& min_corner,
                                       const Eigen::Vector3d& max_corner,
                                       const RoomStyles& styles = {}, double wall_thickness = 0.2);

  /// Adds a copy of every primitive from index `first` on, turned by 180 deg about the vertical
  /// through centre_xy, with the same materials: seen from the turned viewpoint the copy looks
  /// exactly like the original (twin rooms). Boxes and cylinders only: throws
  /// std::invalid_argument for a prism.
  void addHalfTurnCopies(std::uint32_t first, const Eigen::Vector2d& centre_xy);

  /// Builds the BVH and the textures of all materials. Must be called after the last add* and
  /// before raycast(); adding afterwards requires another build().
  void build();
  bool built() const { return built_; }

  /// Closest hit of origin + t*dir, t in (0, max_range]; dir must be a unit vector.
  bool raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_range,
               Hit& hit) const;
  /// Same result, faster for coherent rays: the primitive hit by a neighbouring ray is tested
  /// first, so the BVH search starts with a tight distance bound. Any hint value is valid
  /// (out-of-range hints are ignored).
  bool raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_range,
               Hit& hit, std::uint32_t hint_primitive) const;
  /// Same answer as raycast() by testing every primitive (reference for tests).
  bool raycastBruteForce(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                         double max_range, Hit& hit) const;

  // --- low level, for renderers that cull primitives themselves (e.g. per image tile) ---
  /// Bounds of one primitive (valid after build()).
  const Eigen::AlignedBox3d& primitiveBounds(std::uint32_t prim) const { return bounds_[prim]; }
  /// Distance and face of the ray's hit on one primitive, t in (0, t_max].
  bool intersectPrimitive(std::uint32_t prim, const Eigen::Vector3d& origin,
                          const Eigen::Vector3d& dir, double t_max, PrimitiveHit& hit) const {
    return intersectRef(prim, origin, dir, t_max, hit);
  }
  /// Fills point, normal, material and texture coordinates of a hit found on primitive prim.
  void completeHit(std::uint32_t prim, const PrimitiveHit& ph, const Eigen::Vector3d& origin,
                   const Eigen::Vector3d& dir, Hit& hit) const {
    fillHit(prim, ph, origin, dir, hit);
  }
  /// The ordering raycast() uses: nearer first, equal distances to the lower primitive index
  /// (best.face < 0 means "no hit yet").
  static bool closerHit(const PrimitiveHit& h, std::uint32_t prim, const PrimitiveHit& best,
                        std::uint32_t best_prim) {
    return best.face < 0 || h.t < best.t || (h.t == best.t && prim < best_prim);
  }

  std::size_t primitiveCount() const { return refs_.size(); }
  std::size_t materialCount() const { return materials_.size(); }
  std::uint64_t seed() const { return seed_; }
  /// Bounds of all primitives.
  Eigen::AlignedBox3d bounds() const;
  const Bvh& bvh() const { return bvh_; }

  /// Texture lookup for renderers: colour (R,G,B in [0, 255]) of a material at uv [m] for a
  /// pixel footprint [m]. Requires build().
  Eigen::Vector3f surfaceColor(MaterialId material, const Eigen::Vector2d& uv_m,
                               double footprint_m) const {
    return textures_.sample(appearances_[material], uv_m, footprint_m);
  }

 private:
  enum class Kind : std::uint8_t { Box, Cylinder, Prism };
  struct Ref {
    Kind kind;
    std::uint32_t index;
  };
  std::uint32_t addRef(Kind kind, std::size_t index);
  void requireBuilt(const char* what) const;
  bool intersectRef(std::uint32_t prim, const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                    double t_max, PrimitiveHit& hit) const;
  void fillHit(std::uint32_t prim, const PrimitiveHit& ph, const Eigen::Vector3d& origin,
               const Eigen::Vector3d& dir, Hit& hit) const;

  std::uint64_t seed_;
  std::vector<Material> materials_;
  std::vector<MaterialAppearance> appearances_;
  struct MaterialMirror {
    MaterialId id, source;
    double length_m;
  };
  std::vector<MaterialMirror> mirrors_;  ///< applied by build() after resolving the sources
  std::vector<Box> boxes_;
  std::vector<Cylinder> cylinders_;
  std::vector<Prism> prisms_;
  std::vector<Ref> refs_;
  std::vector<Eigen::AlignedBox3d> bounds_;  ///< per primitive, filled by build()
  Bvh bvh_;
  TextureBank textures_;
  bool built_ = false;
};

}  // namespace rgbdi::sim
