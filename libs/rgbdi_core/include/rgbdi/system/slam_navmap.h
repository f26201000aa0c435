// The navigation maps of a run (doc/navigation-maps.md): built from the same points as map.ply
// (the keyframes' kept points at their loop-corrected poses, those seen within [navmap]
// max_depth_m) and the positions of the best-estimate trajectory (where the robot drove), in
// the run's gravity-aligned world frame.
#pragma once

#include <nlohmann/json.hpp>

#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

/// The keyframes' kept points (those of map.ply) in the world at the keyframes' poses, except
/// those deeper than options.max_depth_m in their keyframe's camera.
std::vector<Eigen::Vector3f> navMapPoints(const mapping::KeyframeStore& store,
                                          const navmap::NavMapOptions& options);
/// The same for one keyframe, appended to `out` (navMapPoints is these in keyframe order).
void appendNavMapPoints(const mapping::Keyframe& keyframe, const navmap::NavMapOptions& options,
                        std::vector<Eigen::Vector3f>* out);

/// Throws std::invalid_argument when the run has no pose.
navmap::NavMap slamNavMap(const SlamSystem& system, const navmap::NavMapOptions& options);

/// summary.json's "navmap": cells per state, their area, the path height, the build time.
nlohmann::json navMapSummary(const navmap::NavMap& map, double build_ms);

}  // namespace rgbdi::system
