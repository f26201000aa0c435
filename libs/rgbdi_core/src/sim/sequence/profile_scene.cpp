#include "rgbdi/sim/profile_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sim/motion/counter_gaussian.h"

namespace rgbdi::sim {
namespace {

// Furniture layout does not depend on the noise seed (only textures do); world_seed 0 is this
// fixed layout, other world seeds offset it.
constexpr std::uint64_t kLayoutSeed = 0x3c6ef372fe94f82bULL;
// Stream of the furniture-slot draws (furniture_density), apart from the layout's streams
// (kind + 1) so that a density of 1 leaves the layout draws untouched.
constexpr std::uint64_t kSlotStream = 1000;

std::uint64_t layoutSeed(std::uint64_t world_seed) { return kLayoutSeed + world_seed; }

/// Deterministic draws for the layout.
class LayoutRandom {
 public:
  LayoutRandom(std::uint64_t seed, std::uint64_t stream) : rng_(seed, stream) {}
  double uniform(double a, double b) { return a + (b - a) * rng_.uniform(n_++); }
  bool chance(double p) { return rng_.uniform(n_++) < p; }
  TextureStyle style() {
    return static_cast<TextureStyle>(
        std::min<int>(kTextureStyleCount - 1, static_cast<int>(uniform(0, kTextureStyleCount))));
  }

 private:
  CounterRng rng_;
  std::uint64_t n_ = 0;
};

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(1e-12, ab.squaredNorm()), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

/// A piece of furniture as a footprint circle (for spacing) and what to add to the scene.
struct Item {
  Eigen::Vector2d center;
  double radius = 0.0;
};

class Furnisher {
 public:
  /// layout: the profile's layout with the room actually built (room_margin_m applied).
  Furnisher(const ProfileLayout& layout, double lateral_max_m, Scene& scene)
      : l_(layout), lateral_max_m_(lateral_max_m), scene_(scene) {}

  /// True when a footprint circle keeps clear of the path corridor, ramps, platforms, walls and
  /// the items placed so far.
  bool free(const Eigen::Vector2d& c, double r) const {
    const ProfileLayout& l = l_;
    if (c.x() - r < l.room_min.x() + 0.05 || c.x() + r > l.room_max.x() - 0.05 ||
        c.y() - r < l.room_min.y() + 0.05 || c.y() + r > l.room_max.y() - 0.05)
      return false;
    for (const Eigen::Vector2d& q : l.path_xy)
      if ((q - c).norm() < l.path_clearance_m + r) return false;
    for (const RampLayout& ramp : l.ramps)
      if (distanceToSegment(c, ramp.from, ramp.to) < 0.5 * ramp.width + r + 0.1) return false;
    for (const PlatformLayout& pl : l.platforms) {
      const Eigen::Vector2d d(std::cos(pl.yaw), std::sin(pl.yaw));
      if (distanceToSegment(c, pl.center - 0.5 * pl.size.x() * d,
                            pl.center + 0.5 * pl.size.x() * d) < 0.5 * pl.size.y() + r + 0.1)
        return false;
    }
    for (const Item& it : items_)
      if ((it.center - c).norm() < it.radius + r + 0.15) return false;
    // Twin rooms: the whole footprint on the first room's side of the partition.
    if (keep_side_ && keep_side_normal_.dot(c - keep_side_point_) < r + 0.15) return false;
    return true;
  }
  /// Keeps furniture away from a footprint placed by someone else (the navigation features).
  void reserve(const Eigen::Vector2d& c, double r) { items_.push_back({c, r}); }
  /// Only footprints entirely on the side of the line through `point` that `normal` points to.
  void keepSide(const Eigen::Vector2d& point, const Eigen::Vector2d& normal) {
    keep_side_ = true;
    keep_side_point_ = point;
    keep_side_normal_ = normal;
  }

  /// Tries to put one object beside path point i on the given side (+1 left, -1 right);
  /// returns whether it fitted.
  bool tryPlace(std::size_t i, double side, bool handheld, LayoutRandom& rnd) {
    const auto& xy = l_.path_xy;
    const Eigen::Vector2d t =
        (xy[std::min(i + 1, xy.size() - 1)] - xy[i > 0 ? i - 1 : 0]).normalized();
    const Eigen::Vector2d n(-t.y(), t.x());
    const double heading = std::atan2(t.y(), t.x());
    // Furniture stands on the floor (z 0 for the synthesised profiles, below a recording's path).
    const double floor = l_.room_min.z(), ceiling = l_.room_max.z();
    const double kind = rnd.uniform(0.0, 1.0);
    const double lateral_extra = rnd.uniform(0.05, lateral_max_m_);
    const double along = rnd.uniform(-0.3, 0.3);
    auto at = [&](double r) {
      return Eigen::Vector2d(xy[i] + side * (l_.path_clearance_m + r + lateral_extra) * n +
                             along * t);
    };
    if (kind < 0.18) {
      // Pillar from floor to ceiling.
      const double r = rnd.uniform(0.1, 0.25);
      const Eigen::Vector2d c = at(r);
      if (!free(c, r)) return false;
      scene_.addCylinder(c, r, floor, ceiling, rnd.style());
      items_.push_back({c, r});
    } else if (kind < 0.45) {
      // Cabinet / shelf facing the path.
      const Eigen::Vector2d size(rnd.uniform(0.35, 0.6), rnd.uniform(0.6, 1.3));
      const double r = 0.5 * size.norm();
      const Eigen::Vector2d c = at(r);
      if (!free(c, r)) return false;
      const double h = handheld ? rnd.uniform(1.2, 2.1) : rnd.uniform(0.6, 1.6);
      scene_.addStep(c, size, heading + 0.5 * M_PI, floor, h,
                     rnd.chance(0.5) ? TextureStyle::Shelves : rnd.style());
      items_.push_back({c, r});
    } else if (kind < 0.6 && handheld) {
      // Table with a few things on it (seen from above by a hand-held camera).
      const Eigen::Vector2d size(rnd.uniform(0.6, 1.2), rnd.uniform(0.5, 0.8));
      const double r = 0.5 * size.norm();
      const Eigen::Vector2d c = at(r);
      if (!free(c, r)) return false;
      const double yaw = heading + rnd.uniform(-0.4, 0.4);
      scene_.addStep(c, size, yaw, floor, 0.75, rnd.style());
      for (int k = 0; k < 2; ++k) {
        const Eigen::Vector2d off(rnd.uniform(-0.25, 0.25) * size.x(),
                                  rnd.uniform(-0.25, 0.25) * size.y());
        const double s = rnd.uniform(0.12, 0.3);
        scene_.addStep(c + Eigen::Rotation2Dd(yaw) * off, {s, s * rnd.uniform(0.7, 1.3)},
                       rnd.uniform(-M_PI, M_PI), floor + 0.75, rnd.uniform(0.08, 0.35),
                       rnd.style());
      }
      items_.push_back({c, r});
    } else {
      // Crate, sometimes with a smaller one on top.
      const double s = rnd.uniform(0.3, 0.8);
      const Eigen::Vector2d size(s, s * rnd.uniform(0.7, 1.4));
      const double r = 0.5 * size.norm();
      const Eigen::Vector2d c = at(r);
      if (!free(c, r)) return false;
      const double yaw = rnd.uniform(-M_PI, M_PI);
      const double h = handheld ? rnd.uniform(0.4, 1.1) : rnd.uniform(0.3, 0.9);
      scene_.addStep(c, size, yaw, floor, h, rnd.style());
      if (rnd.chance(0.4)) {
        const double s2 = 0.6 * s;
        scene_.addStep(c, {s2, s2}, yaw + rnd.uniform(-0.6, 0.6), floor + h, rnd.uniform(0.2, 0.5),
                       rnd.style());
      }
      items_.push_back({c, r});
    }
    return true;
  }

 private:
  const ProfileLayout& l_;
  double lateral_max_m_;
  Scene& scene_;
  std::vector<Item> items_;
  bool keep_side_ = false;
  Eigen::Vector2d keep_side_point_ = Eigen::Vector2d::Zero(),
                  keep_side_normal_ = Eigen::Vector2d::Zero();
};

/// The partition of twin rooms: a floor-to-ceiling wall through `centre` along `dir` across the
/// room, with a door of `door_m` centred at distance `door_at_m` on either side of the centre.
void addPartition(Scene& scene, const ProfileLayout& l, const Eigen::Vector2d& centre,
                  const Eigen::Vector2d& dir, double door_at_m, double door_m) {
  // Distance from the centre to the room's wall along +dir (the room is centred on it).
  double reach = 1e9;
  for (int k = 0; k < 2; ++k)
    if (std::abs(dir[k]) > 1e-9)
      reach = std::min(reach, (dir[k] > 0 ? l.room_max[k] - centre[k] : centre[k] - l.room_min[k]) /
                                  std::abs(dir[k]));
  const double yaw = std::atan2(dir.y(), dir.x());
  const double thickness = 0.1, floor = l.room_min.z(), height = l.room_max.z() - l.room_min.z();
  const double a = door_at_m - 0.5 * door_m, b = door_at_m + 0.5 * door_m;
  // Along dir: [-reach, -b], [-a, a], [b, reach].
  const std::array<std::pair<double, double>, 3> spans{{{-reach, -b}, {-a, a}, {b, reach}}};
  for (const auto& [s0, s1] : spans) {
    if (s1 <= s0) continue;
    const Eigen::Vector2d c = centre + 0.5 * (s0 + s1) * dir;
    scene.addStep(c, {s1 - s0, thickness}, yaw, floor, height, TextureStyle::Posters);
  }
}

// The navigation-map features (ProfileSceneOptions::nav_features).
constexpr double kHoleDepthM = 0.3, kHoleSideM = 0.6;
constexpr double kStepLowM = 0.06, kStepHighM = 0.15;
constexpr double kTableTopM = 0.70, kTableThicknessM = 0.04, kTableLegM = 0.05;

/// A place beside the path for a footprint of radius r near lap fraction `at` (either side, two
/// distances from the corridor, then further along); throws when there is none.
std::pair<Eigen::Vector2d, double> featurePlace(const ProfileLayout& l, const Furnisher& f,
                                                std::size_t lap_samples, double at, double r,
                                                const char* what) {
  const auto& xy = l.path_xy;
  for (std::size_t k = 0; k < lap_samples; k += 5) {
    const std::size_t i = (static_cast<std::size_t>(at * lap_samples) + k) % lap_samples;
    const Eigen::Vector2d t =
        (xy[std::min(i + 1, xy.size() - 1)] - xy[i > 0 ? i - 1 : 0]).normalized();
    const Eigen::Vector2d n(-t.y(), t.x());
    for (double side : {1.0, -1.0})
      for (double extra : {0.15, 0.5}) {
        const Eigen::Vector2d c = xy[i] + side * (l.path_clearance_m + r + extra) * n;
        if (f.free(c, r)) return {c, std::atan2(t.y(), t.x())};
      }
  }
  throw std::invalid_argument(std::string("[sim] nav_features: no room for the ") + what +
                              " beside the path");
}

/// Step, hole and table beside the path; the floor becomes a deck with the hole cut in it (the
/// room itself was built kHoleDepthM deeper).
void addNavFeatures(Scene& scene, const ProfileLayout& l, Furnisher& f, std::size_t lap_samples) {
  const double step_r = 0.5 * std::hypot(1.0, 0.6);
  const auto [step_c, step_yaw] = featurePlace(l, f, lap_samples, 0.15, step_r, "step");
  f.reserve(step_c, step_r);
  scene.addStep(step_c, {1.0, 0.6}, step_yaw, 0.0, kStepLowM, TextureStyle::Planks);
  const Eigen::Vector2d along(std::cos(step_yaw), std::sin(step_yaw));
  scene.addStep(step_c + 0.25 * along, {0.5, 0.6}, step_yaw, kStepLowM, kStepHighM - kStepLowM,
                TextureStyle::Bricks);

  const double hole_r = 0.5 * std::sqrt(2.0) * kHoleSideM;
  const Eigen::Vector2d hole_c = featurePlace(l, f, lap_samples, 0.45, hole_r, "hole").first;
  f.reserve(hole_c, hole_r);
  const Eigen::Vector2d h0 = hole_c.array() - 0.5 * kHoleSideM,
                        h1 = hole_c.array() + 0.5 * kHoleSideM;
  const Eigen::Vector2d r0 = l.room_min.head<2>(), r1 = l.room_max.head<2>();
  auto deck = [&](const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
    if (hi.x() <= lo.x() || hi.y() <= lo.y()) return;
    scene.addStep(0.5 * (lo + hi), hi - lo, 0.0, -kHoleDepthM, kHoleDepthM, TextureStyle::Tiles);
  };
  deck(r0, {h0.x(), r1.y()});
  deck({h1.x(), r0.y()}, r1);
  deck({h0.x(), r0.y()}, {h1.x(), h0.y()});
  deck({h0.x(), h1.y()}, {h1.x(), r1.y()});

  const double table_r = 0.5 * std::hypot(0.9, 0.6);
  const auto [table_c, table_yaw] = featurePlace(l, f, lap_samples, 0.75, table_r, "table");
  f.reserve(table_c, table_r);
  scene.addStep(table_c, {0.9, 0.6}, table_yaw, kTableTopM, kTableThicknessM, TextureStyle::Planks);
  const Eigen::Rotation2Dd R(table_yaw);
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0}) {
      const Eigen::Vector2d leg(sx * (0.45 - 0.03 - 0.5 * kTableLegM),
                                sy * (0.3 - 0.03 - 0.5 * kTableLegM));
      scene.addStep(table_c + R * leg, {kTableLegM, kTableLegM}, table_yaw, 0.0, kTableTopM,
                    TextureStyle::Speckle);
    }
}

}  // namespace

Scene buildProfileScene(const MotionProfile& profile, std::uint64_t seed,
                        const ProfileSceneOptions& options) {
  options.validate();
  ProfileLayout l = profile.layout;
  l.room_min.head<2>().array() -= options.room_margin_m;
  l.room_max.head<2>().array() += options.room_margin_m;
  TextureOptions textures;
  textures.contrast = options.texture_contrast;
  Scene scene(seed, textures);
  RoomStyles room;
  room.aliased_x_walls = options.aliased_walls;
  // The navigation features' hole needs ground below the floor: the room goes deeper and its
  // floor becomes a deck (addNavFeatures).
  Eigen::Vector3d room_min = l.room_min;
  if (options.nav_features) room_min.z() -= kHoleDepthM;
  scene.addRoom(room_min, l.room_max, room);
  for (const RampLayout& r : l.ramps) {
    if (r.symmetric)
      scene.addSymmetricRamp(r.from, r.to, 0.0, r.width, r.height, TextureStyle::Planks);
    else
      scene.addRamp(r.from, r.to, 0.0, r.width, r.height, TextureStyle::Planks);
  }
  for (const PlatformLayout& p : l.platforms)
    scene.addStep(p.center, p.size, p.yaw, 0.0, p.height, TextureStyle::Speckle);

  // Furniture every ~0.8 m of path on both sides (a few draws each; rejected where it would
  // block the corridor, a ramp or another object). One lap suffices: later laps retrace the
  // same ground.
  const bool twin = options.twin_rooms;
  if (twin && profile.kind != ProfileKind::WheeledCircle)
    throw std::invalid_argument(
        "[sim] twin_rooms needs the wheeled_circle profile (its path is "
        "symmetric about the room's centre), not " +
        toString(profile.kind));
  if (twin && options.nav_features)
    throw std::invalid_argument("[sim] nav_features and twin_rooms cannot be combined");
  const Eigen::Vector2d centre = 0.5 * (l.room_min + l.room_max).head<2>();
  Eigen::Vector2d split_dir = Eigen::Vector2d::UnitX();
  if (twin) {
    split_dir = (l.path_xy.front() - centre).normalized();
    const double r = (l.path_xy.front() - centre).norm();
    addPartition(scene, l, centre, split_dir, r, 2.0 * l.path_clearance_m + 0.4);
  }
  const std::uint32_t first_furniture = static_cast<std::uint32_t>(scene.primitiveCount());
  Furnisher furnisher(l, options.furniture_lateral_max_m, scene);
  // Twin rooms: furniture on one side of the partition only (the other side gets its copy).
  if (twin) furnisher.keepSide(centre, Eigen::Vector2d(-split_dir.y(), split_dir.x()));
  const std::uint64_t layout_seed = layoutSeed(options.world_seed);
  LayoutRandom rnd(layout_seed, static_cast<std::uint64_t>(profile.kind) + 1);
  const CounterRng slot_rng(layout_seed, kSlotStream);
  std::uint64_t slot = 0;
  // A recording (hand-held or flying) gets the taller furniture and tables of the hand-held world.
  const bool handheld =
      profile.kind == ProfileKind::Handheld || profile.kind == ProfileKind::Recorded;
  const std::size_t lap_samples = std::min(
      l.path_xy.size(), static_cast<std::size_t>(std::ceil(profile.lap_length_m / 0.1)) + 1);
  if (options.nav_features) addNavFeatures(scene, l, furnisher, lap_samples);
  for (std::size_t i = 0; i < lap_samples; i += 8)
    for (double side : {1.0, -1.0}) {
      // The slot draw has its own stream: at density 1 nothing is drawn and the layout is the
      // one of density 1 in every earlier version.
      if (options.furniture_density < 1.0 &&
          !(slot_rng.uniform(slot++) < options.furniture_density))
        continue;
      for (int attempt = 0; attempt < 3; ++attempt)
        if (furnisher.tryPlace(i, side, handheld, rnd)) break;
    }
  if (twin) scene.addHalfTurnCopies(first_furniture, centre);
  scene.build();
  return scene;
}

}  // namespace rgbdi::sim
