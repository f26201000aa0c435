// The true navigation map of a simulated world (doc/navigation-maps.md "Ground truth"): the
// scene's solids rasterised on the grid and classified by the same rules as an estimated map
// (navmap::buildNavMap), with the true path. The points stand for a complete, noise-free view:
// on 2 x 2 vertical lines per cell, the top of every solid the line crosses (the union of the
// primitives it passes through, solids that touch merged) and, where the top of the solid
// standing on the lowest ground differs between a cell's lines by more than kFaceMinM (a
// vertical face inside the cell: wall, box side, step, table leg, the rim of a hole), points
// every kFaceStepM up that face.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"
#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/sim/scene.h"
#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {

/// [m] height difference between the tops under two lines 2.5 cm apart that counts as a face
/// (a slope of 39 deg; the worlds' ramps rise 0.4 cm over that distance).
inline constexpr double kFaceMinM = 0.02;
/// [m] spacing of the points up a face.
inline constexpr double kFaceStepM = 0.01;

/// The surface points (map frame) of a built scene on `grid`.
std::vector<Eigen::Vector3f> worldSurfacePoints(const Scene& scene,
                                                const navmap::GridGeometry& grid);

/// Body positions of the true path, one per camera frame.
std::vector<Eigen::Vector3d> truePath(const SimulatedSequence& sequence);

/// The true navigation map of a sequence: its world's surface points on the grid around the
/// true path (navmap::gridAroundPath), classified with `options` and the true path.
navmap::NavMap trueNavMap(const SimulatedSequence& sequence, const navmap::NavMapOptions& options);

}  // namespace rgbdi::sim
