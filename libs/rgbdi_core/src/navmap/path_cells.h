// What the path tells the grid: the cells the robot's footprint covered, and for every cell the
// path pose nearest to it horizontally (its distance too), found by propagating the nearest
// pose between neighbouring cells (two raster passes each way; exact for a path whose cells are
// all seeds, within a fraction of a cell otherwise).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"

namespace rgbdi::navmap::detail {

/// 1 where the centre of a cell lies within radius of the path: of a pose, or of the segment
/// between consecutive poses closer than max_join_m horizontally.
std::vector<std::uint8_t> footprintCells(const std::vector<Eigen::Vector3d>& path,
                                         const GridGeometry& grid, double radius,
                                         double max_join_m);

struct NearestPose {
  std::vector<std::int32_t> pose;  ///< per cell: index into the path (-1: no pose in the grid)
  std::vector<float> distance_m;   ///< [m] horizontal distance from the cell centre to it
};
NearestPose nearestPoses(const std::vector<Eigen::Vector3d>& path, const GridGeometry& grid);

}  // namespace rgbdi::navmap::detail
