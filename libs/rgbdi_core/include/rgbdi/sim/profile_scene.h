// The world of each motion profile: a room around the path, the ramps / platform the profile's
// height profile drives over, and furniture (crates, cabinets, pillars, tables) placed along
// both sides of the path, so that textured structure is within about 0.5-4 m of the camera
// everywhere (the D435's depth is only good to ~3 m). The path corridor stays free.
#pragma once

#include <cstdint>

#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {

/// Appearance choices of a profile's world beyond the seed.
struct ProfileSceneOptions {
  /// Perceptual aliasing: the room's +x wall shows the -x wall's texture as seen from the
  /// half-turned viewpoint (RoomStyles::aliased_x_walls), so a camera facing either end wall
  /// from point-symmetric places sees the same wall image.
  bool aliased_walls = false;
};

/// Builds (and build()s) the scene of a profile. The geometry is the same for every seed; the
/// seed drives the textures only.
Scene buildProfileScene(const MotionProfile& profile, std::uint64_t seed,
                        const ProfileSceneOptions& options = {});

}  // namespace rgbdi::sim
