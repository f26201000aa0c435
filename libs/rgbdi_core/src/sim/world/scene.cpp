#include "rgbdi/sim/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/render/det_random.h"

namespace rgbdi::sim {

Scene::Scene(std::uint64_t seed, const TextureOptions& texture_options)
    : seed_(seed), textures_(seed, texture_options) {}

MaterialId Scene::addMaterial(TextureStyle style) {
  const MaterialId id = static_cast<MaterialId>(materials_.size());
  materials_.push_back({style, detail::mixSeed(seed_, 0x6d61746cULL + id)});
  built_ = false;
  return id;
}

void Scene::aliasMaterialMirrored(MaterialId target, MaterialId source, double mirror_length_m) {
  if (source >= materials_.size() || target >= materials_.size())
    throw std::invalid_argument("Scene::aliasMaterialMirrored: unknown material id " +
                                std::to_string(std::max(source, target)));
  if (!std::isfinite(mirror_length_m))
    throw std::invalid_argument("Scene::aliasMaterialMirrored: mirror length must be finite");
  materials_[target] = materials_[source];
  mirrors_.push_back({target, source, mirror_length_m});
  built_ = false;
}

const Material& Scene::material(MaterialId id) const {
  if (id >= materials_.size())
    throw std::out_of_range("Scene::material: unknown material id " + std::to_string(id));
  return materials_[id];
}

std::uint32_t Scene::addRef(Kind kind, std::size_t index) {
  refs_.push_back({kind, static_cast<std::uint32_t>(index)});
  built_ = false;
  return static_cast<std::uint32_t>(refs_.size() - 1);
}

std::uint32_t Scene::addBox(const Eigen::Isometry3d& T_world_box,
                            const Eigen::Vector3d& half_extents, TextureStyle style) {
  std::array<MaterialId, Box::kFaces> m{};
  for (auto& id : m) id = addMaterial(style);
  return addBox(T_world_box, half_extents, m);
}

std::uint32_t Scene::addBox(const Eigen::Isometry3d& T_world_box,
                            const Eigen::Vector3d& half_extents,
                            const std::array<MaterialId, Box::kFaces>& materials) {
  for (MaterialId id : materials) material(id);  // validates
  boxes_.emplace_back(T_world_box, half_extents, materials);
  return addRef(Kind::Box, boxes_.size() - 1);
}

std::uint32_t Scene::addCylinder(const Eigen::Vector2d& center_xy, double radius, double z_min,
                                 double z_max, TextureStyle style) {
  std::array<MaterialId, Cylinder::kFaces> m{};
  for (auto& id : m) id = addMaterial(style);
  cylinders_.emplace_back(center_xy, radius, z_min, z_max, m);
  return addRef(Kind::Cylinder, cylinders_.size() - 1);
}

std::uint32_t Scene::addPrism(const Eigen::Isometry3d& T_world_prism,
                              const std::array<Eigen::Vector2d, 3>& profile_xz, double half_width,
                              TextureStyle style) {
  std::array<MaterialId, Prism::kFaces> m{};
  for (auto& id : m) id = addMaterial(style);
  prisms_.emplace_back(T_world_prism, profile_xz, half_width, m);
  return addRef(Kind::Prism, prisms_.size() - 1);
}

void Scene::addHalfTurnCopies(std::uint32_t first, const Eigen::Vector2d& centre_xy) {
  Eigen::Isometry3d H = Eigen::Isometry3d::Identity();
  H.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  H.translation() = Eigen::Vector3d(2.0 * centre_xy.x(), 2.0 * centre_xy.y(), 0.0);
  const std::size_t n = refs_.size();
  for (std::size_t i = first; i < n; ++i) {
    const Ref r = refs_[i];
    if (r.kind == Kind::Box) {
      const Box b = boxes_[r.index];
      std::array<MaterialId, Box::kFaces> m{};
      for (int f = 0; f < Box::kFaces; ++f) m[static_cast<std::size_t>(f)] = b.material(f);
      addBox(H * b.T_world_box(), b.halfExtents(), m);
    } else if (r.kind == Kind::Cylinder) {
      const Cylinder c = cylinders_[r.index];
      std::array<MaterialId, Cylinder::kFaces> m{};
      for (int f = 0; f < Cylinder::kFaces; ++f) m[static_cast<std::size_t>(f)] = c.material(f);
      cylinders_.emplace_back(Eigen::Vector2d(2.0 * centre_xy - c.centerXY()), c.radius(), c.zMin(),
                              c.zMax(), m);
      addRef(Kind::Cylinder, cylinders_.size() - 1);
    } else {
      throw std::invalid_argument("Scene::addHalfTurnCopies: primitive " + std::to_string(i) +
                                  " is a prism (only boxes and cylinders are copied)");
    }
  }
}

namespace {

// Frame whose x axis runs horizontally from `from` to `to`, z up, origin at `from` on base_z.
Eigen::Isometry3d rampFrame(const Eigen::Vector2d& from_xy, const Eigen::Vector2d& to_xy,
                            double base_z, double& length) {
  const Eigen::Vector2d d = to_xy - from_xy;
  length = d.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    throw std::invalid_argument("Scene: ramp start and end must be distinct finite points");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(std::atan2(d.y(), d.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(from_xy.x(), from_xy.y(), base_z);
  return T;
}

void checkRampSize(double width, double height) {
  if (!(width > 0.0) || !(height > 0.0) || !std::isfinite(width) || !std::isfinite(height))
    throw std::invalid_argument("Scene: ramp width and height must be positive and finite");
}

}  // namespace

std::uint32_t Scene::addRamp(const Eigen::Vector2d& from_xy, const Eigen::Vector2d& to_xy,
                             double base_z, double width, double height, TextureStyle style) {
  checkRampSize(width, height);
  double length = 0.0;
  const Eigen::Isometry3d T = rampFrame(from_xy, to_xy, base_z, length);
  return addPrism(
      T, {Eigen::Vector2d(0, 0), Eigen::Vector2d(length, 0), Eigen::Vector2d(length, height)},
      0.5 * width, style);
}

std::uint32_t Scene::addSymmetricRamp(const Eigen::Vector2d& from_xy, const Eigen::Vector2d& to_xy,
                                      double base_z, double width, double height,
                                      TextureStyle style) {
  checkRampSize(width, height);
  double length = 0.0;
  const Eigen::Isometry3d T = rampFrame(from_xy, to_xy, base_z, length);
  return addPrism(
      T, {Eigen::Vector2d(0, 0), Eigen::Vector2d(length, 0), Eigen::Vector2d(0.5 * length, height)},
      0.5 * width, style);
}

std::uint32_t Scene::addStep(const Eigen::Vector2d& center_xy, const Eigen::Vector2d& size_xy,
                             double yaw, double base_z, double height, TextureStyle style) {
  if (!(size_xy.array() > 0.0).all() || !(height > 0.0))
    throw std::invalid_argument("Scene::addStep: size and height must be positive");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(center_xy.x(), center_xy.y(), base_z + 0.5 * height);
  return addBox(T, Eigen::Vector3d(0.5 * size_xy.x(), 0.5 * size_xy.y(), 0.5 * height), style);
}

std::array<std::uint32_t, 6> Scene::addRoom(const Eigen::Vector3d& min_corner,
                                            const Eigen::Vector3d& max_corner,
                                            const RoomStyles& styles, double wall_thickness) {
  if (!((max_corner - min_corner).array() > 0.0).all() || !min_corner.allFinite() ||
      !max_corner.allFinite())
    throw std::invalid_argument(
        "Scene::addRoom: need finite min_corner < max_corner on every axis");
  if (!(wall_thickness > 0.0))
    throw std::invalid_argument("Scene::addRoom: wall thickness must be positive");
  const double w = wall_thickness;
  // Slabs extend by the wall thickness beyond the interior on every side so corners are closed.
  auto slab = [&](Eigen::Vector3d lo, Eigen::Vector3d hi, TextureStyle style) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = 0.5 * (lo + hi);
    return addBox(T, 0.5 * (hi - lo), style);
  };
  const Eigen::Vector3d lo = min_corner - Eigen::Vector3d::Constant(w);
  const Eigen::Vector3d hi = max_corner + Eigen::Vector3d::Constant(w);
  std::array<std::uint32_t, 6> ids{};
  ids[0] = slab(lo, {hi.x(), hi.y(), min_corner.z()}, styles.floor);
  ids[1] = slab({lo.x(), lo.y(), max_corner.z()}, hi, styles.ceiling);
  ids[2] = slab({lo.x(), lo.y(), min_corner.z()}, {min_corner.x(), hi.y(), max_corner.z()},
                styles.walls[0]);
  ids[3] = slab({max_corner.x(), lo.y(), min_corner.z()}, {hi.x(), hi.y(), max_corner.z()},
                styles.walls[1]);
  if (styles.aliased_x_walls) {
    // Both slabs span y in [lo.y, hi.y] and their inner faces (the -x wall's +x face, the +x
    // wall's -x face) both take u = y - lo.y, so the half-turn image of y has u' = L - u.
    const MaterialId minus_x_inner = boxes_[refs_[ids[2]].index].material(1);
    const MaterialId plus_x_inner = boxes_[refs_[ids[3]].index].material(0);
    aliasMaterialMirrored(plus_x_inner, minus_x_inner, hi.y() - lo.y());
  }
  ids[4] = slab({min_corner.x(), lo.y(), min_corner.z()},
                {max_corner.x(), min_corner.y(), max_corner.z()}, styles.walls[2]);
  ids[5] = slab({min_corner.x(), max_corner.y(), min_corner.z()},
                {max_corner.x(), hi.y(), max_corner.z()}, styles.walls[3]);
  return ids;
}

void Scene::build() {
  bounds_.clear();
  bounds_.reserve(refs_.size());
  for (const Ref& r : refs_) {
    switch (r.kind) {
      case Kind::Box:
        bounds_.push_back(boxes_[r.index].bounds());
        break;
      case Kind::Cylinder:
        bounds_.push_back(cylinders_[r.index].bounds());
        break;
      case Kind::Prism:
        bounds_.push_back(prisms_[r.index].bounds());
        break;
    }
  }
  bvh_.build(bounds_);
  appearances_.clear();
  appearances_.reserve(materials_.size());
  for (const Material& m : materials_) appearances_.push_back(textures_.resolve(m));
  for (const MaterialMirror& m : mirrors_)
    appearances_[m.id] = mirroredAppearance(appearances_[m.source], m.length_m);
  built_ = true;
}

void Scene::requireBuilt(const char* what) const {
  if (!built_)
    throw std::logic_error(std::string("Scene::") + what +
                           ": call build() after adding primitives and before using the scene");
}

Eigen::AlignedBox3d Scene::bounds() const {
  Eigen::AlignedBox3d b;
  for (const Box& x : boxes_) b.extend(x.bounds());
  for (const Cylinder& x : cylinders_) b.extend(x.bounds());
  for (const Prism& x : prisms_) b.extend(x.bounds());
  return b;
}

bool Scene::intersectRef(std::uint32_t prim, const Eigen::Vector3d& origin,
                         const Eigen::Vector3d& dir, double t_max, PrimitiveHit& hit) const {
  const Ref r = refs_[prim];
  switch (r.kind) {
    case Kind::Box:
      return boxes_[r.index].intersect(origin, dir, t_max, hit);
    case Kind::Cylinder:
      return cylinders_[r.index].intersect(origin, dir, t_max, hit);
    case Kind::Prism:
      return prisms_[r.index].intersect(origin, dir, t_max, hit);
  }
  return false;
}

void Scene::fillHit(std::uint32_t prim, const PrimitiveHit& ph, const Eigen::Vector3d& origin,
                    const Eigen::Vector3d& dir, Hit& hit) const {
  hit.t = ph.t;
  hit.point = origin + ph.t * dir;
  hit.primitive = prim;
  hit.face = ph.face;
  const Ref r = refs_[prim];
  SurfaceInfo s;
  switch (r.kind) {
    case Kind::Box:
      s = boxes_[r.index].surface(hit.point, ph.face);
      hit.material = boxes_[r.index].material(ph.face);
      break;
    case Kind::Cylinder:
      s = cylinders_[r.index].surface(hit.point, ph.face);
      hit.material = cylinders_[r.index].material(ph.face);
      break;
    case Kind::Prism:
      s = prisms_[r.index].surface(hit.point, ph.face);
      hit.material = prisms_[r.index].material(ph.face);
      break;
  }
  // Seen from inside a solid the outward normal points away from the viewer: flip it.
  hit.normal = s.normal.dot(dir) > 0.0 ? Eigen::Vector3d(-s.normal) : s.normal;
  hit.uv = s.uv;
}

bool Scene::raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_range,
                    Hit& hit) const {
  return raycast(origin, dir, max_range, hit, std::numeric_limits<std::uint32_t>::max());
}

bool Scene::raycast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double max_range,
                    Hit& hit, std::uint32_t hint_primitive) const {
  requireBuilt("raycast");
  PrimitiveHit best;
  std::uint32_t best_prim = 0;
  double t_start = max_range;
  if (hint_primitive < refs_.size() && intersectRef(hint_primitive, origin, dir, max_range, best)) {
    best_prim = hint_primitive;
    t_start = best.t;
  }
  bvh_.traverse(origin, dir, t_start, [&](std::uint32_t prim, double& t_max) {
    PrimitiveHit ph;
    if (intersectRef(prim, origin, dir, t_max, ph) && closerHit(ph, prim, best, best_prim)) {
      best = ph;
      best_prim = prim;
      t_max = ph.t;
    }
  });
  if (best.face < 0) return false;
  fillHit(best_prim, best, origin, dir, hit);
  return true;
}

bool Scene::raycastBruteForce(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                              double max_range, Hit& hit) const {
  requireBuilt("raycastBruteForce");
  PrimitiveHit best;
  std::uint32_t best_prim = 0;
  double t_max = max_range;
  for (std::uint32_t prim = 0; prim < refs_.size(); ++prim) {
    PrimitiveHit ph;
    if (intersectRef(prim, origin, dir, t_max, ph) && closerHit(ph, prim, best, best_prim)) {
      best = ph;
      best_prim = prim;
      t_max = ph.t;
    }
  }
  if (best.face < 0) return false;
  fillHit(best_prim, best, origin, dir, hit);
  return true;
}

}  // namespace rgbdi::sim
