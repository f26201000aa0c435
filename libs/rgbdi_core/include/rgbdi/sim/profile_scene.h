// The world of each motion profile: a room around the path, the ramps / platform the profile's
// height profile drives over, and furniture (crates, cabinets, pillars, tables) placed along
// both sides of the path, so that textured structure is within about 0.5-4 m of the camera
// everywhere (the D435's depth is only good to ~3 m). The path corridor stays free.
#pragma once

#include <cstdint>

#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {

/// Builds (and build()s) the scene of a profile. The geometry is the same for every seed; the
/// seed drives the textures only.
Scene buildProfileScene(const MotionProfile& profile, std::uint64_t seed);

}  // namespace rgbdi::sim
