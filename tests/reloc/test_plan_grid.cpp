// PlanGrid: known samples -> known occupied, free, unknown and floor cells.
#include <gtest/gtest.h>

#include "reloc_test_worlds.h"
#include "rgbdi/reloc/plan_grid.h"

using namespace rgbdi::reloc;
using rgbdi::reloc::test::at;

namespace {
PlanGridOptions options() {
  PlanGridOptions o;
  o.resolution_m = 0.05;
  o.band_min_m = -0.2;
  o.band_max_m = 0.5;
  o.max_range_m = 4.0;
  return o;
}
}  // namespace

TEST(PlanGrid, AWallSampleIsOccupiedAndTheRayToItFree) {
  const Eigen::Vector3d cam(at(0), at(0), 0.3);
  const PlanGrid g = PlanGrid::build({{cam, Eigen::Vector3d(at(20), at(0), 0.3)}}, options());
  ASSERT_EQ(g.width(), 21);
  ASSERT_EQ(g.height(), 1);
  EXPECT_DOUBLE_EQ(g.corner().x(), 0.0);
  EXPECT_EQ(g.state(20, 0), CellState::kOccupied);
  EXPECT_EQ(g.hits(20, 0), 1);
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(g.state(i, 0), CellState::kFree) << i;
    EXPECT_EQ(g.misses(i, 0), 1) << i;
  }
  EXPECT_EQ(g.state(21, 0), CellState::kUnknown);  // outside
  EXPECT_EQ(g.count(CellState::kOccupied), 1u);
  EXPECT_EQ(g.count(CellState::kFree), 20u);
  EXPECT_TRUE(g.freeInterior(18, 0));
  EXPECT_FALSE(g.freeInterior(19, 0));  // next to the wall
}

TEST(PlanGrid, AFloorSampleKeepsItsHeightAndFreesOnlyTheRayInsideTheBand) {
  // Camera 0.3 m above the floor looking at the floor 1 m ahead: the ray leaves the band
  // (0.2 m below the camera) two thirds of the way, at x = 0.025 + 0.6667 m (cell 13).
  const Eigen::Vector3d cam(at(0), at(0), 0.3);
  const PlanGrid g = PlanGrid::build({{cam, Eigen::Vector3d(at(20), at(0), 0.0)}}, options());
  for (int i = 0; i <= 13; ++i) EXPECT_EQ(g.state(i, 0), CellState::kFree) << i;
  for (int i = 14; i <= 20; ++i) EXPECT_EQ(g.state(i, 0), CellState::kUnknown) << i;
  double z = -1.0;
  ASSERT_TRUE(g.floorHeight(20, 0, &z));
  EXPECT_DOUBLE_EQ(z, 0.0);
  EXPECT_FALSE(g.floorHeight(19, 0, &z));
}

TEST(PlanGrid, CeilingSamplesAndFarSamplesAreNoObstacles) {
  const Eigen::Vector3d cam(at(0), at(0), 0.3);
  const PlanGrid g = PlanGrid::build({{cam, Eigen::Vector3d(at(10), at(0), 2.3)},    // ceiling
                                      {cam, Eigen::Vector3d(at(0), at(100), 0.3)}},  // 5 m away
                                     options());
  EXPECT_EQ(g.height(), 1);  // the far sample is not used at all
  EXPECT_EQ(g.count(CellState::kOccupied), 0u);
  // 0.5 m above the camera is reached at a quarter of the 2 m rise: x = 0.025 + 0.125.
  for (int i = 0; i <= 3; ++i) EXPECT_EQ(g.state(i, 0), CellState::kFree) << i;
  EXPECT_EQ(g.state(4, 0), CellState::kUnknown);
}

TEST(PlanGrid, RaysThroughACellOutnumberingItsHitsMakeItFree) {
  const Eigen::Vector3d cam(at(0), at(0), 0.3);
  std::vector<DepthSample> s{{cam, Eigen::Vector3d(at(5), at(0), 0.3)}};  // a spurious hit
  for (int k = 0; k < 2; ++k) s.push_back({cam, Eigen::Vector3d(at(10), at(0), 0.3)});
  const PlanGrid g = PlanGrid::build(s, options());
  EXPECT_EQ(g.hits(5, 0), 1);
  EXPECT_EQ(g.misses(5, 0), 2);
  EXPECT_EQ(g.state(5, 0), CellState::kFree);
  EXPECT_EQ(g.state(10, 0), CellState::kOccupied);
}

TEST(PlanGrid, DiagonalRaysVisitEveryCellTheyCross) {
  const Eigen::Vector3d cam(at(0), at(0), 0.3);
  const PlanGrid g = PlanGrid::build({{cam, Eigen::Vector3d(at(3), at(2), 0.3)}}, options());
  // From (0.025, 0.025) to (0.175, 0.125) it crosses x = 0.05 at y = 0.042 into (1,0), y = 0.05
  // at x = 0.063 into (1,1), x = 0.1 at y = 0.075 into (2,1), y = 0.1 at x = 0.138 into (2,2)
  // and x = 0.15 at y = 0.108 into (3,2), the wall.
  EXPECT_EQ(g.state(0, 0), CellState::kFree);
  EXPECT_EQ(g.state(1, 0), CellState::kFree);
  EXPECT_EQ(g.state(1, 1), CellState::kFree);
  EXPECT_EQ(g.state(2, 1), CellState::kFree);
  EXPECT_EQ(g.state(2, 2), CellState::kFree);
  EXPECT_EQ(g.state(3, 2), CellState::kOccupied);
  EXPECT_EQ(g.count(CellState::kFree), 5u);
}

TEST(PlanGrid, NoUsableSampleGivesAnEmptyPlan) {
  const PlanGrid g = PlanGrid::build({}, options());
  EXPECT_EQ(g.width(), 0);
  EXPECT_EQ(g.count(CellState::kOccupied), 0u);
}
