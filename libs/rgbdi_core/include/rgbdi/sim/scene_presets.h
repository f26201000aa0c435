// Ready-made scenes: a furnished room representative of the indoor spaces rgbdi targets, used
// by the renderer benchmark and tests, and usable as a starting point for motion profiles.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {

struct FurnishedRoomOptions {
  Eigen::Vector3d size{12.0, 10.0, 3.0};  ///< [m] interior, centred on x = y = 0, floor at z = 0
  int objects = 144;                      ///< furniture pieces (each one primitive)
  /// [m] radius around the room centre kept free of objects (room for a robot to drive).
  double free_radius = 2.5;
};

/// A closed room with shelves and cabinets along the walls, pillars, crates, steps and ramps,
/// placed deterministically from the seed. Objects never enter the central free disc. The
/// returned scene is built.
Scene makeFurnishedRoom(std::uint64_t seed, const FurnishedRoomOptions& options = {});

}  // namespace rgbdi::sim
