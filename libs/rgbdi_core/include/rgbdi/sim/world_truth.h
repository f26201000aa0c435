// The true navigation map of a simulated world (doc/navigation-maps.md "Ground truth"): the
// scene's solids rasterised on the grid and classified by the same rules as an estimated map
// (navmap::buildNavMap), with the true path. The points stand for a complete, noise-free view:
// on kLinesPerSide x kLinesPerSide vertical lines per cell (a quarter cell apart, the outer ones
// at the cell's edges), the top of every solid the line crosses (the union of the primitives it
// passes through, solids that touch merged) and, where the top of the solid standing on the
// lowest ground differs between a cell's lines by more than kFaceMinM (a vertical face inside
// the cell: wall, box side, step, table leg, the rim of a hole), points every kFaceStepM up that
// face. A cell holding any part of a face is thus an obstacle, as a cell holding points of it
// is in an estimate.
//
// One rule differs from an estimate's: a complete view knows what is under a solid. A cell whose
// lowest solid rises from the ground above the robot's clearance (inside a tall box, a wall, a
// table leg) is an obstacle, where an estimate, which sees only its top, leaves it unknown.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"
#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/sim/scene.h"
#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {

/// Vertical lines per cell side.
inline constexpr int kLinesPerSide = 5;
/// [m] height difference between the tops under a cell's lines that counts as a face (the
/// worlds' ramps rise less than 1 cm over a 5 cm cell).
inline constexpr double kFaceMinM = 0.02;
/// [m] spacing of the points up a face.
inline constexpr double kFaceStepM = 0.01;

struct WorldSurface {
  std::vector<Eigen::Vector3f> points;  ///< surface points (map frame)
  /// [m] per cell (GridGeometry order): the highest top, over the cell's lines, of the lowest
  /// solid (NaN where a line meets no solid)
  std::vector<float> column_top_m;
};

/// The surface of a built scene on `grid`.
WorldSurface worldSurface(const Scene& scene, const navmap::GridGeometry& grid);

/// Body positions of the true path, one per camera frame.
std::vector<Eigen::Vector3d> truePath(const SimulatedSequence& sequence);

/// The true map from a world's surface: navmap::buildNavMap of its points, then every unknown
/// cell within range_m of the path whose column top is more than clearance_height_m above the
/// robot's ground (that under the nearest path position) made an obstacle.
navmap::NavMap trueNavMap(const WorldSurface& surface, const std::vector<Eigen::Vector3d>& path,
                          const navmap::NavMapOptions& options, const navmap::GridGeometry& grid);

/// The true navigation map of a sequence on the grid around its true path
/// (navmap::gridAroundPath).
navmap::NavMap trueNavMap(const SimulatedSequence& sequence, const navmap::NavMapOptions& options);

}  // namespace rgbdi::sim
