// The world of each motion profile: a room around the path, the ramps / platform the profile's
// height profile drives over, and furniture (crates, cabinets, pillars, tables) placed along
// both sides of the path, so that textured structure is within about 0.5-4 m of the camera
// everywhere (the D435's depth is only good to ~3 m). The path corridor stays free.
#pragma once

#include <cstdint>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {

/// Choices of a profile's world beyond the seed ([sim] keys). The defaults give the fixed world
/// of each profile; the others vary it within stated ranges (a benchmark draws them per run).
struct ProfileSceneOptions {
  /// Perceptual aliasing: the room's +x wall shows the -x wall's texture as seen from the
  /// half-turned viewpoint (RoomStyles::aliased_x_walls), so a camera facing either end wall
  /// from point-symmetric places sees the same wall image.
  bool aliased_walls = false;
  /// [integer] seed of the furniture layout draw; 0 = the profile's fixed layout. Other values
  /// give other furniture (positions, kinds, sizes) along the same path.
  std::uint64_t world_seed = 0;
  /// [m] added between the profile's room walls and the path on every side (floor plan only;
  /// the ceiling height is kept).
  double room_margin_m = 0.0;
  /// [probability] that a furniture slot (every 0.8 m of path on each side) is used; 0 = an
  /// empty room (walls, floor, ceiling and the profile's ramps / platform only).
  double furniture_density = 1.0;
  /// [m] largest extra lateral distance of furniture from the path corridor (drawn uniformly
  /// from 0.05 m up to this).
  double furniture_lateral_max_m = 0.7;
  /// (0, 1] scales every texture's deviation from its mean colour (low = faint texture).
  double texture_contrast = 1.0;
  /// Two identical rooms (wheeled_circle only): a wall through the room's centre and the
  /// path's start splits it in two, with a door where the circle crosses it; the furniture of
  /// the first half lap is repeated turned by 180 deg about the centre with the same textures,
  /// so each half is the other's twin (geometric relocalisation must see two places, not
  /// guess one). Room walls and the partition's two faces keep their own textures.
  bool twin_rooms = false;
  /// The navigation-map test world (doc/navigation-maps.md): beside the path, a two-level step
  /// (0.06 m, then 0.15 m), a hole (0.6 x 0.6 m, 0.3 m deep: the floor is a 0.3 m deck over the
  /// room's bottom with the hole cut in it) and a table (top 0.70-0.74 m on four 5 cm legs).
  bool nav_features = false;

  /// Reads [sim] aliased_walls, world_seed, room_margin_m, furniture_density,
  /// furniture_lateral_max_m, texture_contrast, twin_rooms, nav_features (ConfigError naming the
  /// key when out of range).
  static ProfileSceneOptions load(IniReader& ini);
  /// Throws std::invalid_argument when a value is out of the ranges load() accepts.
  void validate() const;
};

/// Builds (and build()s) the scene of a profile. With the default options the geometry is the
/// same for every seed (the seed drives the textures only); world_seed and the other options
/// change the furniture and the room. Throws std::invalid_argument for twin_rooms with a profile
/// other than wheeled_circle, and for nav_features when a feature finds no room beside the path.
Scene buildProfileScene(const MotionProfile& profile, std::uint64_t seed,
                        const ProfileSceneOptions& options = {});

}  // namespace rgbdi::sim
