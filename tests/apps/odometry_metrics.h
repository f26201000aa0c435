// The VIO issue's acceptance metrics of one odometry run on a simulated sequence (ATE after
// position+yaw alignment, Sim(3) scale, coverage, start-up time, resets, time offset) and its
// health checks. Shared by the accuracy tests, so that a sequence rendered for a SLAM run is
// also judged as odometry (SlamSystem::odometry() is the same VioSystem that rgbdi-slam runs):
// rendering dominates, and a sequence is rendered once per test.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <string>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/system/vio_system.h"

namespace rgbdi::test {

struct OdometryMetrics {
  double ate_posyaw = 0.0;     ///< [m] ATE RMSE after position+yaw alignment
  double scale = 1.0;          ///< scale of a Sim(3) alignment
  double coverage = 0.0;       ///< share of the sequence with a pose
  double first_pose_s = -1.0;  ///< [s] first pose after the sequence's first image
  int resets = 0;
  bool evaluated = false;      ///< false: fewer than 10 poses (never initialised)
  double time_offset_s = 0.0;  ///< [s] final estimate
};

/// Metrics of `vio` (after endOfStream) against the ground truth of `seq`; prints one table
/// row (the doc/status.md columns) labelled with `label`, e.g. "handheld | 30 Hz".
inline OdometryMetrics measureOdometry(const std::string& label, const sim::SimulatedSequence& seq,
                                       const system::VioSystem& vio, bool no_depth) {
  OdometryMetrics m;
  m.resets = vio.estimatorStats().resets;
  m.time_offset_s = vio.timeOffset();
  if (vio.estimatorStats().first_pose_t_image >= 0)
    m.first_pose_s = vio.estimatorStats().first_pose_t_image - seq.frameStamp(0);
  const Trajectory gt = seq.bodyTrajectory();
  if (vio.trajectoryBody().size() < 10) return m;
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  const auto posyaw = eval::evaluate(gt, vio.trajectoryBody(), eo);
  eo.align = eval::AlignMode::Sim3;
  const auto sim3 = eval::evaluate(gt, vio.trajectoryBody(), eo);
  m.ate_posyaw = posyaw.ate.rmse;
  m.scale = sim3.alignment.scale;
  m.coverage = posyaw.coverage.coverage;
  m.evaluated = true;
  std::cout << std::fixed << std::setprecision(4) << "| " << label << " | "
            << (no_depth ? "mono-inertial" : "rgbd-inertial") << " | ATE " << m.ate_posyaw
            << " m | scale error " << std::abs(m.scale - 1.0) * 100.0 << " % | coverage "
            << m.coverage * 100.0 << " % | first pose " << m.first_pose_s << " s | resets "
            << m.resets << " | time offset " << 1000.0 * m.time_offset_s << " ms |" << std::endl;
  return m;
}

/// The VIO issue's health criteria of a static-start run: initialised, no reset, coverage
/// >= 99 %, first pose within 1 s of the start.
inline void expectHealthyOdometry(const OdometryMetrics& m) {
  ASSERT_TRUE(m.evaluated) << "the odometry never initialised";
  EXPECT_EQ(m.resets, 0);
  EXPECT_GE(m.coverage, 0.99);
  EXPECT_GE(m.first_pose_s, 0.0);
  EXPECT_LE(m.first_pose_s, 1.0);  // static start: no waiting for excitation
}

}  // namespace rgbdi::test
