// buildNavMap on synthetic point sets with known answers: a flat floor, a box, a ramp of known
// slope, a step, a hole, a table whose top is above the clearance band, a ceiling, low
// obstacles, the robot's footprint.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "rgbdi/navmap/nav_map.h"

using namespace rgbdi::navmap;

namespace {

constexpr double kCell = 0.05;

/// Points on 4 x 4 sub-positions of every cell whose centre lies in [x0, x1) x [y0, y1) (cell
/// edges on multiples of kCell), at height z(x, y). Sub-positions keep clear of cell edges.
void addSurface(std::vector<Eigen::Vector3f>& pts, double x0, double x1, double y0, double y1,
                const std::function<double(double, double)>& z) {
  for (int ix = static_cast<int>(std::lround(x0 / kCell)); ix < std::lround(x1 / kCell); ++ix)
    for (int iy = static_cast<int>(std::lround(y0 / kCell)); iy < std::lround(y1 / kCell); ++iy)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double x = (ix + (a + 0.5) / 4.0) * kCell, y = (iy + (b + 0.5) / 4.0) * kCell;
          pts.emplace_back(x, y, z(x, y));
        }
}
void addFlat(std::vector<Eigen::Vector3f>& pts, double x0, double x1, double y0, double y1,
             double z) {
  addSurface(pts, x0, x1, y0, y1, [z](double, double) { return z; });
}
/// A vertical face from z0 to z1 (1 cm apart) in every cell of the rectangle.
void addColumn(std::vector<Eigen::Vector3f>& pts, double x0, double x1, double y0, double y1,
               double z0, double z1) {
  for (double z = z0; z <= z1 + 1e-9; z += 0.01) addFlat(pts, x0, x1, y0, y1, z);
}

std::vector<Eigen::Vector3d> straightPath(double x0, double x1, double y, double z) {
  std::vector<Eigen::Vector3d> p;
  for (double x = x0; x <= x1 + 1e-9; x += 0.1) p.emplace_back(x, y, z);
  return p;
}

/// State of the cell whose centre is nearest to (x, y).
std::size_t cellAt(const NavMap& m, double x, double y) {
  int ix = 0, iy = 0;
  EXPECT_TRUE(m.grid.cellOf(x, y, &ix, &iy)) << x << " " << y;
  return m.grid.index(ix, iy);
}
CellState stateAt(const NavMap& m, double x, double y) { return m.state[cellAt(m, x, y)]; }

}  // namespace

TEST(NavMap, FlatFloorIsFreeAtItsHeightAndUnseenCellsUnknown) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 1.0, 0.0);
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_NEAR(m.path_height_m, 0.3, 1e-6);
  EXPECT_EQ(m.count(CellState::kFree), 80u * 40u);  // the floor's cells, all in range
  EXPECT_EQ(m.count(CellState::kFree) + m.count(CellState::kUnknown), m.grid.cellCount());
  const std::size_t c = cellAt(m, 1.0125, 0.0125);
  EXPECT_EQ(m.ground_z_m[c], 0.0f);
  EXPECT_EQ(m.ground_sigma_m[c], 0.0f);
  EXPECT_NEAR(m.slope_deg[c], 0.0, 1e-6);
  EXPECT_EQ(m.step_m[c], 0.0f);
  EXPECT_NEAR(m.roughness_m[c], 0.0, 1e-6);
  EXPECT_EQ(m.traversability[c], 1.0f);
  EXPECT_EQ(stateAt(m, 3.2, 0.0), CellState::kUnknown);
  EXPECT_TRUE(std::isnan(m.ground_z_m[cellAt(m, 3.2, 0.0)]));
  EXPECT_EQ(m.occupancy(c), kOccFree);
  EXPECT_EQ(m.occupancy(cellAt(m, 3.2, 0.0)), kOccUnknown);
}

TEST(NavMap, CellsBeyondTheRangeAreUnknown) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 1.0, 0.0);
  NavMapOptions o;
  o.range_m = 0.5;
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), o);
  EXPECT_EQ(stateAt(m, 1.0, 0.475), CellState::kFree);     // 0.475 m from the path
  EXPECT_EQ(stateAt(m, 1.0, 0.525), CellState::kUnknown);  // 0.525 m
}

TEST(NavMap, BoxSidesAreObstaclesAndItsTopIsARaisedPlateau) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 0.0);
  // 0.4 x 0.4 m box, 0.3 m high, at x [1.0, 1.4), y [0.5, 0.9): its side faces in the outer
  // ring of cells, its top everywhere.
  std::vector<Eigen::Vector3f> box;
  addColumn(box, 1.0, 1.4, 0.5, 0.9, 0.0, 0.3);
  for (const Eigen::Vector3f& p : box) {
    const bool ring = p.x() < 1.05 || p.x() > 1.35 || p.y() < 0.55 || p.y() > 0.85;
    if (ring || p.z() > 0.295f) pts.push_back(p);
  }
  // Remove the floor under the box (not seen).
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [](const Eigen::Vector3f& p) {
                             return p.z() == 0.0f && p.x() > 1.05 && p.x() < 1.35 && p.y() > 0.55 &&
                                    p.y() < 0.85;
                           }),
            pts.end());
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(m.count(CellState::kObstacle), 28u);  // the 8 x 8 box's outer ring
  EXPECT_EQ(m.count(CellState::kStepEdge), 20u);  // the top's cells next to that ring
  EXPECT_EQ(m.count(CellState::kRaised), 16u);    // the rest of the top
  EXPECT_EQ(stateAt(m, 1.025, 0.525), CellState::kObstacle);
  EXPECT_EQ(stateAt(m, 1.075, 0.575), CellState::kStepEdge);
  EXPECT_EQ(stateAt(m, 1.175, 0.675), CellState::kRaised);
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.175, 0.675)], 0.3, 1e-6);
  EXPECT_EQ(stateAt(m, 0.975, 0.525), CellState::kFree);  // the floor beside it
  EXPECT_EQ(m.occupancy(cellAt(m, 1.175, 0.675)), kOccOccupied);
  // The footprint (0.2 m) centred within 0.2 m of the box touches it: traversability 0.
  EXPECT_EQ(m.traversability[cellAt(m, 0.875, 0.675)], 0.0f);
  EXPECT_EQ(m.traversability[cellAt(m, 0.725, 0.675)], 1.0f);
}

TEST(NavMap, LowObstaclesAreKeptAndClimbableOnesAreNot) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 0.0);
  addColumn(pts, 1.0, 1.05, 0.5, 0.55, 0.0, 0.12);  // 12 cm: above max_step_m 0.1
  addColumn(pts, 1.5, 1.55, 0.5, 0.55, 0.0, 0.08);  // 8 cm: below it
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(stateAt(m, 1.025, 0.525), CellState::kObstacle);
  EXPECT_EQ(stateAt(m, 1.525, 0.525), CellState::kFree);
  EXPECT_EQ(m.count(CellState::kObstacle), 1u);
}

TEST(NavMap, RampOfKnownSlopeIsTraversableOrTooSteep) {
  const double slope = 10.0 * M_PI / 180.0, top = std::tan(slope);
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 1.0, -1.0, 1.0, 0.0);
  addSurface(pts, 1.0, 2.0, -1.0, 1.0,
             [slope](double x, double) { return std::tan(slope) * (x - 1.0); });
  addFlat(pts, 2.0, 3.0, -1.0, 1.0, top);
  std::vector<Eigen::Vector3d> path;
  for (double x = 0.0; x <= 2.6; x += 0.1)
    path.emplace_back(x, 0.0, 0.3 + std::clamp(x - 1.0, 0.0, 1.0) * top);
  NavMap m = buildNavMap(pts, path, NavMapOptions{});
  const std::size_t c = cellAt(m, 1.5125, 0.5125);
  EXPECT_EQ(m.state[c], CellState::kFree);
  EXPECT_NEAR(m.slope_deg[c], 10.0, 1e-3);
  EXPECT_NEAR(m.roughness_m[c], 0.0, 1e-5);
  EXPECT_NEAR(m.step_m[c], kCell * top, 1e-5);
  EXPECT_NEAR(m.traversability[c], 0.5, 1e-3);  // 1 - 10 / 20 deg
  EXPECT_EQ(m.count(CellState::kTooSteep), 0u);
  // A robot limited to 8 deg: the ramp beside its path is too steep, the path itself is free.
  NavMapOptions o;
  o.max_slope_deg = 8.0;
  path.clear();
  for (double x = 0.0; x <= 0.9; x += 0.1) path.emplace_back(x, 0.0, 0.3);
  m = buildNavMap(pts, path, o);
  EXPECT_EQ(stateAt(m, 1.5125, 0.5125), CellState::kTooSteep);
  EXPECT_EQ(stateAt(m, 0.5, 0.0), CellState::kFree);
}

TEST(NavMap, StepHigherThanMaxStepHasAnEdgeAndALowerOneDoesNot) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 1.5, -1.0, 1.0, 0.0);
  addColumn(pts, 1.5, 1.55, -1.0, 0.0, 0.0, 0.15);  // 15 cm step at y < 0
  addFlat(pts, 1.55, 2.5, -1.0, 0.0, 0.15);
  addFlat(pts, 1.5, 2.5, 0.0, 0.2, 0.0);
  addFlat(pts, 1.5, 2.5, 0.2, 1.0, 0.06);  // 6 cm step at y >= 0.2 (no face points: a small one)
  const NavMap m = buildNavMap(pts, straightPath(0.0, 1.0, 0.5, 0.3), NavMapOptions{});
  EXPECT_EQ(stateAt(m, 1.525, -0.5), CellState::kObstacle);  // the face
  EXPECT_EQ(stateAt(m, 1.575, -0.5), CellState::kStepEdge);  // upper side
  EXPECT_EQ(stateAt(m, 2.0, -0.5), CellState::kRaised);      // not connected, 15 cm up
  EXPECT_EQ(stateAt(m, 1.475, -0.5), CellState::kFree);      // the foot of the step
  EXPECT_EQ(stateAt(m, 1.525, 0.5), CellState::kFree);
  EXPECT_EQ(stateAt(m, 2.0, 0.5), CellState::kFree);
  const std::size_t c = cellAt(m, 1.525, 0.5);
  EXPECT_NEAR(m.step_m[c], 0.06, 1e-6);
  // Two footprints (plane fit, then traversability) beyond the small step the ground is level;
  // on it, the step's margin (and the
  // slope and roughness of a plane across it) limit the traversability.
  EXPECT_NEAR(m.traversability[cellAt(m, 2.025, 0.625)], 1.0, 1e-6);
  EXPECT_GT(m.traversability[c], 0.0f);
  EXPECT_LE(m.traversability[c], 1.0 - 0.06 / 0.1 + 1e-6);
}

TEST(NavMap, HoleIsNotTraversableAndItsRimIsAnEdge) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 0.0);
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [](const Eigen::Vector3f& p) {
                             return p.x() > 1.0 && p.x() < 1.3 && p.y() > 0.3 && p.y() < 0.6;
                           }),
            pts.end());
  addFlat(pts, 1.0, 1.3, 0.3, 0.6, -0.3);
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(m.count(CellState::kLowered), 36u);             // 6 x 6 cells of the hole's bottom
  EXPECT_EQ(m.count(CellState::kStepEdge), 8u * 8u - 36u);  // the ring of floor around it
  EXPECT_EQ(stateAt(m, 1.15, 0.45), CellState::kLowered);
  EXPECT_EQ(stateAt(m, 0.975, 0.45), CellState::kStepEdge);
  EXPECT_EQ(stateAt(m, 0.925, 0.45), CellState::kFree);
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.15, 0.45)], -0.3, 1e-6);
}

TEST(NavMap, AHoleWallSeenOnlyAFewCentimetresDownIsADropNotFloor) {
  // The hole x in [1.0, 1.3), y in [0.3, 0.6): its bottom unseen (as from a camera 0.35 m up, 2-3 m
  // away), only its far wall (the cells x in [1.25, 1.3)) seen from the floor 8 cm down. A 6 cm
  // step beside it (y in [1.0, 1.5)) shows its riser going up from the floor, and a 6 cm step
  // down (y in [-1.0, -0.5)) its face and the lower floor at its foot.
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 0.0);
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [](const Eigen::Vector3f& p) {
                             return (p.x() > 1.0 && p.x() < 1.3 && p.y() > 0.3 && p.y() < 0.6) ||
                                    (p.x() > 1.5 && p.x() < 2.0 && p.y() > 1.0 && p.y() < 1.5) ||
                                    (p.x() > 1.5 && p.x() < 2.0 && p.y() > -1.0 && p.y() < -0.5);
                           }),
            pts.end());
  addColumn(pts, 1.25, 1.3, 0.3, 0.6, -0.08, 0.0);
  addColumn(pts, 1.5, 1.55, 1.0, 1.5, 0.0, 0.06);
  addFlat(pts, 1.55, 2.0, 1.0, 1.5, 0.06);
  addColumn(pts, 1.5, 1.55, -1.0, -0.5, -0.06, 0.0);  // the face, with the lower floor at its foot
  addFlat(pts, 1.5, 2.0, -1.0, -0.5, -0.06);
  const auto path = straightPath(0.0, 2.0, 0.0, 0.3);
  const NavMap m = buildNavMap(pts, path, NavMapOptions{});
  // The wall's cells: lowest surface the mean of the points within 4 cm of the 3rd lowest
  // (-8..-4 cm: -6 cm), points up to 0: a 6 cm rise from 6 cm below the floor.
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.275, 0.45)], -0.06, 1e-6);
  EXPECT_EQ(stateAt(m, 1.275, 0.45), CellState::kStepEdge);
  EXPECT_EQ(stateAt(m, 1.325, 0.45), CellState::kStepEdge);  // the rim beyond, 6 cm above
  EXPECT_EQ(stateAt(m, 1.375, 0.45), CellState::kFree);
  EXPECT_EQ(stateAt(m, 1.15, 0.45), CellState::kUnknown);  // the hole's inside: unseen
  // The wall (6 cells) and its rim: the 18 cells around it less the 6 inside the hole.
  EXPECT_EQ(m.count(CellState::kStepEdge), 6u + 12u);
  // The riser's lowest surface is the floor (the mean of 0..4 cm: 2 cm): not below the robot's
  // ground, not a drop; the step is climbable.
  EXPECT_EQ(stateAt(m, 1.525, 1.25), CellState::kFree);
  EXPECT_EQ(stateAt(m, 1.575, 1.25), CellState::kFree);
  // The step down: its face's lowest surface (-4.3 cm, 4 cm of rise) is the lower floor's level
  // (-6 cm), seen beside it: a step the robot climbs, not a drop.
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.525, -0.75)], -0.0433333, 1e-6);
  EXPECT_EQ(stateAt(m, 1.525, -0.75), CellState::kFree);
  EXPECT_EQ(stateAt(m, 1.575, -0.75), CellState::kFree);
  // Without the test (drop_face_min_rise_m = 0) the wall joins the floor's plateau as free.
  NavMapOptions off;
  off.drop_face_min_rise_m = 0.0;
  const NavMap plain = buildNavMap(pts, path, off);
  EXPECT_EQ(stateAt(plain, 1.275, 0.45), CellState::kFree);
  EXPECT_EQ(plain.count(CellState::kStepEdge), 0u);
}

TEST(NavMap, TableLegsAreObstaclesAndTheFloorUnderItsTopIsFree) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 0.0);
  addFlat(pts, 1.0, 1.4, 0.4, 0.8, 0.7);  // top above clearance_height_m 0.5
  for (double x : {1.0, 1.35})
    for (double y : {0.4, 0.75}) addColumn(pts, x, x + 0.05, y, y + 0.05, 0.0, 0.7);
  // A second table whose floor was not seen: only its top.
  addFlat(pts, 1.0, 1.4, -1.4, -1.0, 0.7);
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(m.count(CellState::kObstacle), 4u);
  EXPECT_EQ(stateAt(m, 1.025, 0.425), CellState::kObstacle);
  EXPECT_EQ(stateAt(m, 1.2, 0.6), CellState::kFree);
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.2, 0.6)], 0.0, 1e-6);
  EXPECT_EQ(stateAt(m, 1.2, -1.2), CellState::kUnknown);
  // A robot 0.8 m tall does not fit under the top.
  NavMapOptions tall;
  tall.clearance_height_m = 0.8;
  const NavMap t = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), tall);
  EXPECT_EQ(stateAt(t, 1.2, 0.6), CellState::kObstacle);
  EXPECT_EQ(stateAt(t, 1.2, -1.2), CellState::kRaised);  // top alone: a plateau 0.7 m up
}

TEST(NavMap, CeilingIsIgnoredAndAloneLeavesCellsUnknown) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 1.0, 0.0);
  addFlat(pts, -1.0, 3.0, -1.0, 2.0, 2.5);  // the ceiling reaches beyond the seen floor
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(m.count(CellState::kFree), 80u * 40u);
  EXPECT_EQ(m.count(CellState::kFree) + m.count(CellState::kUnknown), m.grid.cellCount());
  EXPECT_EQ(stateAt(m, 1.0, 1.5), CellState::kUnknown);
}

TEST(NavMap, AHandHeldPathOverUnseenFloorTakesItsHeightFromTheFloorBelowIt) {
  // Camera carried at 1.4 m; the floor is seen beside the path (within 1 m of it), never under it,
  // the ceiling (2.5 m) everywhere: the ceiling above the path is no ground under it.
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, 0.5, 1.0, 0.0);
  addFlat(pts, -1.0, 3.0, -0.5, 1.0, 2.5);
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 1.4), NavMapOptions{});
  EXPECT_NEAR(m.path_height_m, 1.4, 1e-6);
  EXPECT_EQ(stateAt(m, 2.0, 0.8), CellState::kFree);
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 2.0, 0.8)], 0.0, 1e-6);
  // Where only the ceiling was seen, beside the footprint: unknown, not a lowered plateau.
  EXPECT_EQ(stateAt(m, 2.0, -0.35), CellState::kUnknown);
}

TEST(NavMap, BoxTopsBesideAHandHeldPathDoNotLiftTheGroundUnderIt) {
  // Camera carried at 1.4 m over unseen floor; within 1 m of it mostly box tops at 0.3 m and a
  // strip of floor (0.5 <= y < 0.6, about 12 % of the cells around each position). The floor is
  // the lowest height band holding at least path_ground_min_fraction (10 %) of those cells: the
  // strip is free floor and the box tops raised. Their median (fraction 1) would put the ground
  // on the box tops and the strip 0.3 m below it, lowered.
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, 0.5, 0.6, 0.0);
  addFlat(pts, -1.0, 3.0, 0.6, 1.0, 0.3);
  addFlat(pts, -1.0, 3.0, -1.0, -0.5, 0.3);
  const auto path = straightPath(0.0, 2.0, 0.0, 1.4);
  const NavMap m = buildNavMap(pts, path, NavMapOptions{});
  EXPECT_NEAR(m.path_height_m, 1.4, 1e-6);
  EXPECT_EQ(stateAt(m, 1.0, 0.525), CellState::kFree);
  EXPECT_EQ(stateAt(m, 1.0, 0.575), CellState::kFree);
  EXPECT_NEAR(m.ground_z_m[cellAt(m, 1.0, 0.525)], 0.0, 1e-6);
  EXPECT_EQ(stateAt(m, 1.0, 0.825), CellState::kRaised);
  EXPECT_EQ(stateAt(m, 1.0, -0.775), CellState::kRaised);

  NavMapOptions median_of_all;
  median_of_all.path_ground_min_fraction = 1.0;
  const NavMap old = buildNavMap(pts, path, median_of_all);
  EXPECT_NEAR(old.path_height_m, 1.1, 1e-6);
  EXPECT_EQ(stateAt(old, 1.0, 0.525), CellState::kLowered);
  EXPECT_EQ(stateAt(old, 1.0, 0.825), CellState::kFree);
}

TEST(NavMap, CellsTheRobotDroveOverAreFree) {
  std::vector<Eigen::Vector3f> pts;
  addFlat(pts, -1.0, 3.0, -1.0, 1.0, 0.0);
  addColumn(pts, 1.0, 1.05, 0.0, 0.05, 0.0, 0.3);  // a spurious obstacle on the path
  addColumn(pts, 1.0, 1.05, 0.5, 0.55, 0.0, 0.3);  // a real one beside it
  const NavMap m = buildNavMap(pts, straightPath(0.0, 2.0, 0.0, 0.3), NavMapOptions{});
  EXPECT_EQ(stateAt(m, 1.025, 0.025), CellState::kFree);
  EXPECT_TRUE(m.driven[cellAt(m, 1.025, 0.025)]);
  EXPECT_EQ(stateAt(m, 1.025, 0.525), CellState::kObstacle);
  // Footprint 0.2 m around the segment y = 0: cell centres up to |y| 0.175 are driven.
  EXPECT_TRUE(m.driven[cellAt(m, 1.0, 0.175)]);
  EXPECT_FALSE(m.driven[cellAt(m, 1.0, 0.225)]);
}

TEST(NavMap, ResultDoesNotDependOnThePointOrder) {
  std::vector<Eigen::Vector3f> pts;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  addFlat(pts, -1.0, 3.0, -1.0, 1.0, 0.0);
  addColumn(pts, 1.0, 1.2, 0.5, 0.7, 0.0, 0.3);
  for (Eigen::Vector3f& p : pts) p.z() += noise(rng);
  const auto path = straightPath(0.0, 2.0, 0.0, 0.3);
  const NavMap a = buildNavMap(pts, path, NavMapOptions{});
  std::shuffle(pts.begin(), pts.end(), rng);
  const NavMap b = buildNavMap(pts, path, NavMapOptions{});
  EXPECT_EQ(a.state, b.state);
  for (std::size_t i = 0; i < a.grid.cellCount(); ++i) {
    if (std::isfinite(a.ground_z_m[i])) {
      EXPECT_NEAR(a.ground_z_m[i], b.ground_z_m[i], 1e-6);
    }
  }
}

TEST(NavMap, RefusesAnEmptyPathAndInvalidOptions) {
  EXPECT_THROW(buildNavMap({}, {}, NavMapOptions{}), std::invalid_argument);
  NavMapOptions o;
  o.clearance_height_m = 0.05;  // below max_step_m
  EXPECT_THROW(buildNavMap({}, straightPath(0, 1, 0, 0.3), o), rgbdi::ConfigError);
  NavMapOptions rise;
  rise.drop_face_min_rise_m = 0.12;  // above max_step_m: such points are obstacles
  try {
    rise.validate();
    FAIL() << "no error";
  } catch (const rgbdi::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("drop_face_min_rise_m: must be at most max_step_m"),
              std::string::npos)
        << e.what();
  }
  NavMapOptions depth;
  depth.drop_face_min_depth_m = -0.01;
  EXPECT_THROW(depth.validate(), rgbdi::ConfigError);
}
