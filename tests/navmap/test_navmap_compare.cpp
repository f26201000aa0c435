// A navigation map against the true one (rgbdi-eval --navmap): exact counts for an identical map,
// a map in a shifted frame, and known disagreements.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/navmap/navmap_compare.h"

using namespace rgbdi::navmap;

namespace {

/// Floor at z0 with a 0.3 m box at (0.6..0.7, 0.6..0.7), all shifted by `shift`.
NavMap floorWithBox(const Eigen::Vector3d& shift) {
  std::vector<Eigen::Vector3f> pts;
  auto flat = [&](double x0, double x1, double y0, double y1, double z) {
    for (double x = x0 + 0.00625; x < x1; x += 0.0125)
      for (double y = y0 + 0.00625; y < y1; y += 0.0125)
        pts.emplace_back((Eigen::Vector3d(x, y, z) + shift).cast<float>());
  };
  flat(-0.5, 1.5, -0.5, 1.0, 0.0);
  for (double z = 0; z <= 0.3; z += 0.01) flat(0.6, 0.7, 0.6, 0.7, z);
  const std::vector<Eigen::Vector3d> path{Eigen::Vector3d(0.0, 0.0, 0.3) + shift,
                                          Eigen::Vector3d(1.0, 0.0, 0.3) + shift};
  NavMapOptions o;
  o.range_m = 1.0;
  return buildNavMap(pts, path, o);
}

}  // namespace

TEST(NavMapCompare, AMapAgreesWithItselfCellForCell) {
  const NavMap m = floorWithBox(Eigen::Vector3d::Zero());
  const NavMapComparison c = compareNavMaps(m, m, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_EQ(c.observed, c.true_known);
  EXPECT_EQ(c.true_free, m.count(CellState::kFree));
  EXPECT_EQ(c.free_as_free, c.true_free);
  EXPECT_EQ(c.true_occupied,
            m.grid.cellCount() - m.count(CellState::kFree) - m.count(CellState::kUnknown));
  EXPECT_GT(c.true_occupied, 0u);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied);
  EXPECT_GT(c.true_driven, 0u);
  EXPECT_EQ(c.driven_as_free, c.true_driven);
  EXPECT_EQ(c.height_cells, c.true_free);
  EXPECT_NEAR(c.height_rmse_m, 0.0, 1e-7);
  EXPECT_EQ(c.confusion[1][1], c.true_free);
}

TEST(NavMapCompare, AMapInAnotherFrameIsComparedThroughTheTransform) {
  // The estimate's frame: the world moved by (0.2, -0.1, 0.05) (whole cells horizontally).
  const Eigen::Vector3d shift(0.2, -0.1, 0.05);
  const NavMap truth = floorWithBox(Eigen::Vector3d::Zero());
  const NavMap est = floorWithBox(shift);
  Eigen::Isometry3d T_est_truth = Eigen::Isometry3d::Identity();
  T_est_truth.translation() = shift;
  const NavMapComparison c = compareNavMaps(est, truth, T_est_truth, 2.0);
  EXPECT_EQ(c.observed, c.true_known);
  EXPECT_EQ(c.free_as_free, c.true_free);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied);
  EXPECT_NEAR(c.height_rmse_m, 0.0, 1e-6);
  // Without the transform the box is in the wrong place and the heights are 5 cm off.
  const NavMapComparison wrong = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_LT(wrong.occupied_as_occupied, wrong.true_occupied);
  EXPECT_NEAR(wrong.height_bias_m, 0.05, 1e-6);
}

TEST(NavMapCompare, KnownDisagreementsAreCountedExactly) {
  const NavMap truth = floorWithBox(Eigen::Vector3d::Zero());
  NavMap est = truth;
  // One free cell estimated as an obstacle, one obstacle as free, one free cell unobserved, and
  // every ground height 2 cm high.
  std::size_t free_cell = 0, obstacle_cell = 0, unseen_cell = 0;
  int found = 0;
  for (std::size_t i = 0; i < truth.grid.cellCount() && found < 3; ++i) {
    if (truth.state[i] == CellState::kFree && !truth.driven[i] && found == 0) {
      free_cell = i;
      ++found;
    } else if (truth.state[i] == CellState::kFree && !truth.driven[i] && found == 2) {
      unseen_cell = i;
      ++found;
    } else if (truth.state[i] == CellState::kObstacle && found == 1) {
      obstacle_cell = i;
      ++found;
    }
  }
  ASSERT_EQ(found, 3);
  est.state[free_cell] = CellState::kObstacle;
  est.state[obstacle_cell] = CellState::kFree;
  est.state[unseen_cell] = CellState::kUnknown;
  for (float& h : est.ground_z_m) h += 0.02f;
  const NavMapComparison c = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_EQ(c.observed, c.true_known - 1);
  EXPECT_EQ(c.true_free, truth.count(CellState::kFree) - 1);
  EXPECT_EQ(c.free_as_free, c.true_free - 1);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied - 1);
  EXPECT_EQ(c.confusion[static_cast<int>(CellState::kFree)][static_cast<int>(CellState::kObstacle)],
            1u);
  EXPECT_EQ(c.height_cells, c.true_free - 1);  // free in both
  EXPECT_NEAR(c.height_rmse_m, 0.02, 1e-6);
  EXPECT_NEAR(c.height_bias_m, 0.02, 1e-6);
}

namespace {

/// Cell index of the point (x, y) in `m`'s grid.
std::size_t cellAt(const NavMap& m, double x, double y) {
  int ix = 0, iy = 0;
  EXPECT_TRUE(m.grid.cellOf(x, y, &ix, &iy));
  return m.grid.index(ix, iy);
}

}  // namespace

TEST(NavMapCompare, AWorldShiftedByAQuarterCellIsRightWithinOneCell) {
  // The estimate saw the world a quarter cell (12.5 mm) off in x and y: the box's faces now lie
  // in the cells beyond the true ones, so its outer ring of cells is an obstacle in the estimate
  // and free in the truth. Strictly those are misses; within one cell of the true face they are
  // right, and every figure is 100 %.
  const NavMap truth = floorWithBox(Eigen::Vector3d::Zero());
  const NavMap est = floorWithBox(Eigen::Vector3d(0.0125, 0.0125, 0.0));
  const NavMapComparison c = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  // The true box: cells x, y in [0.6, 0.7) (2 x 2); the estimate's: [0.6, 0.75) (3 x 3).
  EXPECT_EQ(truth.state[cellAt(truth, 0.725, 0.725)], CellState::kFree);
  EXPECT_EQ(est.state[cellAt(est, 0.725, 0.725)], CellState::kObstacle);
  EXPECT_LT(c.free_as_free, c.true_free);
  EXPECT_EQ(c.true_free - c.free_as_free, 5u);  // the estimate's extra L of 5 cells
  EXPECT_EQ(c.free_tolerated, 5u);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied);
  EXPECT_DOUBLE_EQ(c.freeRecallTolerant(), 1.0);
  EXPECT_DOUBLE_EQ(c.occupiedRecallTolerant(), 1.0);
  EXPECT_EQ(c.toJson()["free_recall_tolerant"].get<double>(), 1.0);
}

TEST(NavMapCompare, OnlyBoundaryDisagreementsWithinOneCellAreTolerated) {
  const NavMap truth = floorWithBox(Eigen::Vector3d::Zero());
  ASSERT_EQ(truth.state[cellAt(truth, 0.625, 0.625)], CellState::kObstacle);
  ASSERT_EQ(truth.state[cellAt(truth, 0.675, 0.675)], CellState::kObstacle);
  // Obstacles in front of the box: the free cell next to its face (a miss strictly, tolerated)
  // and the one two cells from it (a miss in both).
  NavMap est = truth;
  est.state[cellAt(est, 0.575, 0.625)] = CellState::kObstacle;
  est.state[cellAt(est, 0.525, 0.675)] = CellState::kObstacle;
  NavMapComparison c = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_EQ(c.free_as_free, c.true_free - 2);
  EXPECT_EQ(c.free_tolerated, 1u);
  EXPECT_EQ(c.true_free - c.free_as_free - c.free_tolerated, 1u);

  // One box cell estimated free with the other three still obstacles: tolerated.
  est = truth;
  est.state[cellAt(est, 0.625, 0.625)] = CellState::kFree;
  c = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied - 1);
  EXPECT_EQ(c.occupied_tolerated, 1u);
  EXPECT_DOUBLE_EQ(c.occupiedRecallTolerant(), 1.0);

  // The whole box missed: no obstacle within one cell, a miss in both.
  for (double x : {0.625, 0.675})
    for (double y : {0.625, 0.675}) est.state[cellAt(est, x, y)] = CellState::kFree;
  c = compareNavMaps(est, truth, Eigen::Isometry3d::Identity(), 2.0);
  EXPECT_EQ(c.occupied_as_occupied, c.true_occupied - 4);
  EXPECT_EQ(c.occupied_tolerated, 0u);
}
