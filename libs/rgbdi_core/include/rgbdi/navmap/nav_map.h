// Navigation maps for a ground robot, built from the map's points in the gravity-aligned map
// frame (z up) and the path the robot drove (doc/navigation-maps.md):
//
//  * a 2.5-D elevation and traversability grid: per cell the ground height and its spread, the
//    slope of a plane fitted to the ground around it, the largest step to a neighbour, the
//    roughness (RMS residual of that plane) and a traversability value in [0, 1] from the
//    robot's limits (NavMapOptions);
//  * a 2-D trinary occupancy grid derived from it: free where the robot can drive, occupied
//    where it cannot (an obstacle in the band (max_step_m, clearance_height_m] above the ground,
//    ground steeper than max_slope_deg, the upper side of a step or drop beyond max_step_m,
//    ground not level with the robot's and not connected to it: box tops, holes), unknown where
//    nothing was seen. Points above the band are overhangs and ignored; cells whose lowest
//    surface is above the band (a table top with the floor under it unseen) stay unknown.
//
// The ground of a cell is its lowest surface: the mean of the points within ground_band_m of its
// min_points_per_cell-th lowest point. The robot's own ground comes from the path: under each
// path position, the median ground of the cells within path_ground_radius_m below it (where
// none was seen: the position less the median height of the path above that ground), and each
// cell takes the ground under its nearest path position as its reference. Cells the robot's
// footprint covered are free whatever the points say. The result depends only on
// the points (not their order) and the path.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"
#include "rgbdi/navmap/navmap_options.h"

namespace rgbdi::navmap {

/// Why a cell is what it is (the occupancy follows: kUnknown unknown, kFree free, others occupied).
enum class CellState : std::uint8_t {
  kUnknown = 0,   ///< no ground seen (or beyond range_m, or only overhangs)
  kFree = 1,      ///< traversable ground
  kObstacle = 2,  ///< at least min_obstacle_points points in the obstacle band
  kTooSteep = 3,  ///< ground slope above max_slope_deg
  kStepEdge = 4,  ///< upper side of a step or drop higher than max_step_m
  kRaised = 5,    ///< ground above the robot's by more than max_step_m, not connected to it
  kLowered = 6,   ///< ground below the robot's by more than max_step_m (hole, pit), not connected
};
const char* toString(CellState state);

/// Occupancy values (ROS nav_msgs/OccupancyGrid convention).
inline constexpr std::int8_t kOccUnknown = -1;
inline constexpr std::int8_t kOccFree = 0;
inline constexpr std::int8_t kOccOccupied = 100;

/// The layers, one value per cell (GridGeometry order); NaN where the cell has no ground.
struct NavMap {
  GridGeometry grid;
  std::vector<float> ground_z_m;      ///< [m] ground height (map frame z)
  std::vector<float> ground_sigma_m;  ///< [m] standard deviation of the ground points
  std::vector<float> slope_deg;       ///< [deg] slope of the ground plane fitted over the footprint
  std::vector<float> step_m;          ///< [m] largest height difference to a neighbour's ground
  std::vector<float> roughness_m;     ///< [m] RMS residual of that plane
  /// [0, 1] 0 = not traversable; else the least margin left to the robot's slope, step and
  /// roughness limits over the cells its footprint covers when centred here
  std::vector<float> traversability;
  std::vector<CellState> state;
  std::vector<std::uint8_t> driven;  ///< 1 where the robot's footprint passed
  /// [m] height of the path above the ground under it (NaN when no ground was seen near the path)
  double path_height_m = 0.0;

  std::int8_t occupancy(std::size_t i) const {
    return state[i] == CellState::kUnknown
               ? kOccUnknown
               : (state[i] == CellState::kFree ? kOccFree : kOccOccupied);
  }
  std::size_t count(CellState s) const;
};

/// Builds both layers from points (map frame, z up) and the path (positions of the robot body
/// in the same frame, in driving order; consecutive positions closer than range_m are joined,
/// so the footprint covers the segment between them). The grid spans the path's bounding box
/// widened by range_m, its corner a multiple of cell_size_m. Points outside it are ignored.
/// Throws std::invalid_argument for an empty path or invalid options.
NavMap buildNavMap(const std::vector<Eigen::Vector3f>& points,
                   const std::vector<Eigen::Vector3d>& path, const NavMapOptions& options);

/// The same on a given grid (e.g. a ground-truth grid to compare with).
NavMap buildNavMap(const std::vector<Eigen::Vector3f>& points,
                   const std::vector<Eigen::Vector3d>& path, const NavMapOptions& options,
                   const GridGeometry& grid);

/// The grid buildNavMap uses for this path.
GridGeometry gridAroundPath(const std::vector<Eigen::Vector3d>& path, const NavMapOptions& options);

}  // namespace rgbdi::navmap
