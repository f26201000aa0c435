// Redundant-viewpoint test of the map: distance and angle thresholds, cell boundaries, disabling.
#include <gtest/gtest.h>

#include "rgbdi/mapping/viewpoint_index.h"

using namespace rgbdi::mapping;

namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw_deg = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() << x, y, z;
  return T;
}

}  // namespace

TEST(ViewpointIndex, DistanceAndAngleThresholds) {
  ViewpointIndex idx(0.15, 15.0);
  EXPECT_FALSE(idx.covered(pose(0, 0, 0)));  // empty
  idx.add(pose(1.0, 2.0, 0.3, 30.0));
  EXPECT_EQ(idx.size(), 1u);
  EXPECT_TRUE(idx.covered(pose(1.0, 2.0, 0.3, 30.0)));
  EXPECT_TRUE(idx.covered(pose(1.1, 2.0, 0.3, 40.0)));    // 0.10 m, 10 deg
  EXPECT_FALSE(idx.covered(pose(1.16, 2.0, 0.3, 30.0)));  // 0.16 m
  EXPECT_FALSE(idx.covered(pose(1.0, 2.0, 0.3, 46.0)));   // 16 deg
  EXPECT_FALSE(idx.covered(pose(1.0, 2.0, 0.3, 14.0)));   // -16 deg
  EXPECT_TRUE(idx.covered(pose(1.0, 2.0, 0.3, 44.0)));    // 14 deg
}

TEST(ViewpointIndex, NeighboursAcrossCellBoundariesAreFound) {
  ViewpointIndex idx(0.15, 15.0);
  idx.add(pose(0.149, -0.001, 0.0));  // just below a cell boundary on x, just across on y
  EXPECT_TRUE(idx.covered(pose(0.151, 0.001, 0.0)));
  EXPECT_TRUE(idx.covered(pose(0.149, -0.001, -0.1)));  // across z = 0
  EXPECT_FALSE(idx.covered(pose(0.149, 0.2, 0.0)));
}

TEST(ViewpointIndex, ZeroDistanceDisablesTheTest) {
  ViewpointIndex idx(0.0, 15.0);
  idx.add(pose(0, 0, 0));
  EXPECT_FALSE(idx.covered(pose(0, 0, 0)));
  EXPECT_EQ(idx.size(), 1u);
}
