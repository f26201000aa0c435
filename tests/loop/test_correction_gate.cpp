// The correction gate: a loop's disagreement with the odometry in its own sigmas, known answers.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/loop/correction_gate.h"

using rgbdi::loop::CorrectionGateOptions;
using rgbdi::loop::LoopConstraint;
using rgbdi::loop::loopDisagreement;

namespace {
Eigen::Isometry3d pose(double x, double y, double z, double yaw_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).matrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

/// A loop measuring odometry * E: 16 agreeing pairs with an RMS of 2 cm, position sigma 5 mm.
LoopConstraint loopOff(const Eigen::Isometry3d& odom, const Eigen::Isometry3d& E) {
  LoopConstraint c;
  c.T_from_to = odom * E;
  c.depth_inliers = 16;
  c.depth_rms_m = 0.02;
  return c;
}
}  // namespace

TEST(CorrectionGate, PositionDisagreementInTheLoopsStandardError) {
  const Eigen::Isometry3d odom = pose(3.0, -1.0, 0.2, 70.0);
  const LoopConstraint c = loopOff(odom, pose(0.003, 0.004, 0.0, 0.0));  // 5 mm off
  CorrectionGateOptions o;
  const auto d = loopDisagreement(c, odom, o);
  EXPECT_NEAR(d.position_m, 0.005, 1e-12);
  EXPECT_NEAR(d.yaw_deg, 0.0, 1e-9);
  EXPECT_DOUBLE_EQ(d.sigma_position_m, 0.005);  // 0.02 / sqrt(16)
  EXPECT_DOUBLE_EQ(d.sigma_yaw_deg, 0.1);       // 20 deg/m x 5 mm
  EXPECT_NEAR(d.sigmas, 1.0, 1e-9);
  EXPECT_FALSE(d.shows_drift);  // gate 2
  o.gate_sigma = 0.99;
  EXPECT_TRUE(loopDisagreement(c, odom, o).shows_drift);
  o.gate_sigma = 0.0;  // off: every loop corrects
  const LoopConstraint exact = loopOff(odom, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(loopDisagreement(exact, odom, o).shows_drift);
}

TEST(CorrectionGate, TheLargerOfPositionAndYawCounts) {
  const Eigen::Isometry3d odom = pose(-2.0, 4.0, 0.0, -30.0);
  CorrectionGateOptions o;
  // 1 mm and 0.25 deg: 0.2 sigma in position, 2.5 sigma in yaw.
  const auto d = loopDisagreement(loopOff(odom, pose(0.001, 0.0, 0.0, 0.25)), odom, o);
  EXPECT_NEAR(d.position_m, 0.001, 1e-12);
  EXPECT_NEAR(d.yaw_deg, 0.25, 1e-9);
  EXPECT_NEAR(d.sigmas, 2.5, 1e-7);
  EXPECT_TRUE(d.shows_drift);
  // The sign of the yaw does not matter; 12 mm of height is 2.4 sigma.
  EXPECT_NEAR(loopDisagreement(loopOff(odom, pose(0.0, 0.0, 0.0, -0.25)), odom, o).sigmas, 2.5,
              1e-7);
  EXPECT_NEAR(loopDisagreement(loopOff(odom, pose(0.0, 0.0, 0.012, 0.0)), odom, o).sigmas, 2.4,
              1e-9);
}

TEST(CorrectionGate, ThePositionSigmaHasAFloor) {
  const Eigen::Isometry3d odom = pose(1.0, 1.0, 0.0, 10.0);
  LoopConstraint c = loopOff(odom, pose(0.003, 0.0, 0.0, 0.0));
  c.depth_rms_m = 0.0;  // noise-free depth
  CorrectionGateOptions o;
  o.sigma_floor_m = 0.002;
  const auto d = loopDisagreement(c, odom, o);
  EXPECT_DOUBLE_EQ(d.sigma_position_m, 0.002);
  EXPECT_NEAR(d.sigmas, 1.5, 1e-9);
  c.depth_inliers = 0;  // no pairs counted: one, not a division by zero
  c.depth_rms_m = 0.01;
  EXPECT_DOUBLE_EQ(loopDisagreement(c, odom, o).sigma_position_m, 0.01);
}
