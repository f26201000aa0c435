// The true navigation map of a simulated world: a room with a tall box, a step, a hole and a
// table beside a straight path, each cell's state known exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/sim/scene.h"
#include "rgbdi/sim/world_truth.h"

namespace rgbdi::sim {
namespace {

using navmap::CellState;

/// Room floor at z = 0 made of a 0.3 m deck over a deeper bottom, with a 0.6 m hole at (1, -1.2).
Scene testWorld() {
  Scene s(3);
  s.addRoom({-1.0, -2.0, -0.3}, {5.0, 2.0, 2.5});
  auto deck = [&](Eigen::Vector2d lo, Eigen::Vector2d hi) {
    s.addStep(0.5 * (lo + hi), hi - lo, 0.0, -0.3, 0.3, TextureStyle::Tiles);
  };
  deck({-1.0, -2.0}, {0.7, 2.0});
  deck({1.3, -2.0}, {5.0, 2.0});
  deck({0.7, -2.0}, {1.3, -1.5});
  deck({0.7, -0.9}, {1.3, 2.0});
  s.addStep({1.0, 1.0}, {0.4, 0.4}, 0.0, 0.0, 0.8, TextureStyle::Bricks);     // tall box
  s.addStep({2.5, 1.0}, {0.6, 0.6}, 0.0, 0.0, 0.15, TextureStyle::Planks);    // step
  s.addStep({3.5, -1.2}, {0.6, 0.4}, 0.0, 0.70, 0.04, TextureStyle::Planks);  // table top
  for (double x : {3.225, 3.775})
    for (double y : {-1.375, -1.025})
      s.addStep({x, y}, {0.05, 0.05}, 0.0, 0.0, 0.70, TextureStyle::Speckle);
  s.build();
  return s;
}

std::vector<Eigen::Vector3d> straightPath() {
  std::vector<Eigen::Vector3d> p;
  for (double x = 0.0; x <= 4.0 + 1e-9; x += 0.05) p.emplace_back(x, 0.0, 0.3);
  return p;
}

CellState stateAt(const navmap::NavMap& m, double x, double y) {
  int ix = 0, iy = 0;
  EXPECT_TRUE(m.grid.cellOf(x, y, &ix, &iy)) << x << " " << y;
  return m.state[m.grid.index(ix, iy)];
}

float groundAt(const navmap::NavMap& m, double x, double y) {
  int ix = 0, iy = 0;
  EXPECT_TRUE(m.grid.cellOf(x, y, &ix, &iy)) << x << " " << y;
  return m.ground_z_m[m.grid.index(ix, iy)];
}

TEST(WorldTruth, EveryFeatureHasItsTrueState) {
  const Scene scene = testWorld();
  const std::vector<Eigen::Vector3d> path = straightPath();
  const navmap::NavMapOptions o;  // max_step 0.1 m, clearance 0.5 m
  const navmap::GridGeometry grid = navmap::gridAroundPath(path, o);
  const navmap::NavMap m = trueNavMap(worldSurface(scene, grid), path, o, grid);
  EXPECT_NEAR(m.path_height_m, 0.3, 1e-6);
  // Floor: free at height 0, the path free.
  EXPECT_EQ(stateAt(m, 0.4, 0.7), CellState::kFree);
  EXPECT_NEAR(groundAt(m, 0.4, 0.7), 0.0, 1e-6);
  EXPECT_EQ(stateAt(m, 2.0, 0.0), CellState::kFree);
  // Tall box: its sides and, as the truth knows, its inside are obstacles.
  EXPECT_EQ(stateAt(m, 1.0, 1.0), CellState::kObstacle);
  EXPECT_EQ(stateAt(m, 0.81, 1.0), CellState::kObstacle);
  EXPECT_EQ(stateAt(m, 1.0, 0.75), CellState::kFree);
  // Step 0.15 m: its top a raised plateau at 0.15 m with edges, the floor beside it free.
  EXPECT_EQ(stateAt(m, 2.5, 1.0), CellState::kRaised);
  EXPECT_NEAR(groundAt(m, 2.5, 1.0), 0.15, 1e-6);
  EXPECT_EQ(stateAt(m, 2.22, 1.0), CellState::kStepEdge);
  EXPECT_EQ(stateAt(m, 2.5, 0.6), CellState::kFree);
  // Hole 0.3 m deep: its bottom lowered, its rim an edge.
  EXPECT_EQ(stateAt(m, 1.0, -1.2), CellState::kLowered);
  EXPECT_NEAR(groundAt(m, 1.0, -1.2), -0.3, 1e-6);
  EXPECT_EQ(stateAt(m, 1.0, -0.88), CellState::kStepEdge);
  // Table: floor under its top free, the legs (0.70 m, above the clearance) obstacles.
  EXPECT_EQ(stateAt(m, 3.5, -1.2), CellState::kFree);
  EXPECT_NEAR(groundAt(m, 3.5, -1.2), 0.0, 1e-6);
  EXPECT_EQ(stateAt(m, 3.225, -1.025), CellState::kObstacle);
  // The room's walls beyond the floor.
  EXPECT_EQ(stateAt(m, 4.99, 0.0), CellState::kFree);
  EXPECT_EQ(stateAt(m, 5.05, 0.0), CellState::kObstacle);
}

TEST(WorldTruth, CellsBeyondTheRangeStayUnknown) {
  const Scene scene = testWorld();
  const std::vector<Eigen::Vector3d> path{{0.0, 0.0, 0.3}};
  navmap::NavMapOptions o;
  o.range_m = 0.5;
  const navmap::GridGeometry grid = navmap::gridAroundPath(path, o);
  const navmap::NavMap m = trueNavMap(worldSurface(scene, grid), path, o, grid);
  EXPECT_EQ(stateAt(m, 0.3, 0.0), CellState::kFree);
  EXPECT_EQ(m.count(CellState::kObstacle), 0u);
  EXPECT_GT(m.count(CellState::kUnknown), 0u);
}

}  // namespace
}  // namespace rgbdi::sim
