// The two stages of a navigation-map build, shared by the full build (buildNavMap) and the
// incremental one (NavMapUpdater), so that both give the same layers from the same points:
//
//  1. per cell, from its points alone: the lowest surface and whether points lie in the obstacle
//     band above it (cellSurface);
//  2. from those and the path: the ground under the path, overhangs, obstacles, slopes, steps,
//     plateaus and traversability (startNavMap, then finishNavMap).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <vector>

#include "navmap/layer_reuse.h"
#include "navmap/path_cells.h"
#include "rgbdi/navmap/nav_map.h"

namespace rgbdi::navmap::detail {

/// What a cell's points say, before the path is known.
struct CellSurface {
  float ground_z_m = std::numeric_limits<float>::quiet_NaN();  ///< [m] lowest surface
  float sigma_m = std::numeric_limits<float>::quiet_NaN();     ///< [m] its spread
  /// at least min_obstacle_points points in (ground + max_step_m, ground + clearance_height_m]
  bool obstacle = false;
  /// [m] the highest point at most max_step_m above the lowest surface, less that surface: how
  /// far the points rise without being obstacles (0 without a ground)
  float rise_m = 0.0f;
};

/// Stage 1 for the heights [first, last) of one cell's points, ascending.
CellSurface cellSurface(const float* first, const float* last, const NavMapOptions& options);

/// The layers of `grid`, all unknown, with the cells the path's footprint covered, and the
/// nearest path pose of every cell. Throws std::invalid_argument for an empty path or invalid
/// options.
NavMap startNavMap(const std::vector<Eigen::Vector3d>& path, const NavMapOptions& options,
                   const GridGeometry& grid, NearestPose* near);

/// Stage 2: `m` as startNavMap left it with ground_z_m and ground_sigma_m set (stage 1) for the
/// cells within range_m of the path (near.distance_m) and `obstacle` (1 per cell whose stage 1
/// found an obstacle) and `rise` (CellSurface::rise_m per cell, 0 elsewhere); derives every other
/// layer. With a cache (NavMapUpdater), the plane fits and traversability of the cells whose inputs
/// did not change since the cache was filled are taken from it (the same values), and the cache is
/// filled for the next build.
void finishNavMap(NavMap& m, const NearestPose& near, const std::vector<std::uint8_t>& obstacle,
                  const std::vector<float>& rise, const std::vector<Eigen::Vector3d>& path,
                  const NavMapOptions& options, LayerCache* cache = nullptr);

}  // namespace rgbdi::navmap::detail
