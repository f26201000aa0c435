// Loop closure end to end on generated sequences (issue 10, acceptance): loops are found on every
// revisit, every accepted loop agrees with the ground truth, the final trajectory beats the
// odometry, and a sequence that never revisits gets no loop. Runs the same SlamSystem rgbdi-slam
// runs; the wheeled robot at 15 Hz to keep the suite's wall time in budget (doc/loop.md has the
// 30 Hz figures).
//
// The odometry of the same runs is also held to the VIO issue's criteria (the handheld 30 Hz and
// wheeled_circle 15 Hz rows of doc/status.md; the other rows are test_vio_accuracy's): the
// SlamSystem's odometry is the VioSystem rgbdi-slam runs, and loop closing never feeds back into
// it, so each sequence is rendered and estimated once. The wheeled robot's run also feeds the
// monocular baseline the same measurements.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>

#include "odometry_metrics.h"
#include "rgbdi/common/fan_out_sink.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_system.h"

using namespace rgbdi;

namespace {

struct LoopRun {
  double ate_final = 0, ate_online = 0, ate_odometry = 0;
  std::size_t accepted = 0, rolled_back = 0, wrong = 0;
  std::set<int> laps_with_loops;  ///< lap index (from the ground-truth distance) of each query
  int laps = 0;
  test::OdometryMetrics odometry;  ///< the RGB-D odometry of the SLAM run (VIO criteria)
  test::OdometryMetrics mono;      ///< the monocular baseline, when it ran beside
};

double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

/// The SLAM run on a fresh rendering of `so`; `with_monocular`: the monocular baseline is fed
/// the same measurements (rendering costs more than its odometry).
LoopRun runLoops(sim::SimOptions so, bool with_monocular = false) {
  sim::SimulatedSequence seq(so);
  auto ini = IniReader::fromText(sim::slamConfigText(seq), "generated config.ini");
  const system::SystemConfig cfg = system::SystemConfig::load(ini);
  system::SlamSystemOptions opt;
  system::SlamSystem sys(cfg, opt);
  std::unique_ptr<system::VioSystem> mono;
  if (with_monocular) {
    mono = std::make_unique<system::VioSystem>(cfg, false);
    FanOutSink both({&sys, mono.get()});
    seq.pump(both);
  } else {
    seq.pump(sys);
  }

  LoopRun r;
  std::ostringstream label;
  label << sim::toString(so.profile.kind) << " | " << so.fps << " Hz";
  r.odometry = test::measureOdometry(label.str(), seq, sys.odometry(), false);
  if (mono) r.mono = test::measureOdometry(label.str(), seq, *mono, true);
  const Trajectory gt = seq.bodyTrajectory();
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  r.ate_final = eval::evaluate(gt, sys.finalTrajectory(), eo).ate.rmse;
  r.ate_online = eval::evaluate(gt, sys.onlineTrajectory(), eo).ate.rmse;
  r.ate_odometry = eval::evaluate(gt, sys.odometryTrajectory(), eo).ate.rmse;

  // Ground-truth distance travelled at each stamp, for the lap of each loop.
  const double lap = seq.profile().lap_length_m;
  auto distanceAt = [&](double t) {
    double d = 0;
    for (std::size_t i = 1; i < gt.size() && gt[i].t <= t; ++i) {
      const Eigen::Vector2d a = gt[i - 1].p.head<2>(), b = gt[i].p.head<2>();
      d += (b - a).norm();
    }
    return d;
  };
  r.laps = lap > 0 ? static_cast<int>(std::floor(distanceAt(gt.back().t) / lap)) : 0;
  const loop::LoopCloser* lc = sys.loopCloser();
  if (!lc) return r;
  r.accepted = lc->stats().accepted;
  r.rolled_back = lc->stats().rolled_back;
  const auto& kfs = sys.keyframeStates();
  for (const loop::LoopRecord& l : lc->loops()) {
    if (l.rolled_back) continue;
    const double t_from = kfs.at(l.constraint.from_id).state.t_imu;
    const double t_to = kfs.at(l.constraint.to_id).state.t_imu;
    const Eigen::Isometry3d T_true =
        seq.groundTruth(t_from).T_world_body.inverse() * seq.groundTruth(t_to).T_world_body;
    const Eigen::Isometry3d E = T_true.inverse() * l.constraint.T_from_to;
    const bool wrong = E.translation().norm() > 0.10 || std::abs(yawOf(E.rotation())) > 0.05;
    if (wrong) ++r.wrong;
    if (lap > 0) r.laps_with_loops.insert(static_cast<int>(std::floor(distanceAt(t_to) / lap)));
  }
  std::cout << std::fixed << std::setprecision(4) << "| " << sim::toString(so.profile.kind)
            << " | ATE final " << r.ate_final << " m | online " << r.ate_online << " m | odometry "
            << r.ate_odometry << " m | loops " << r.accepted << " (rolled back " << r.rolled_back
            << ", wrong " << r.wrong << ") | laps " << r.laps << " |" << std::endl;
  return r;
}

sim::SimOptions profileOptions(const std::string& profile, double duration_s = 0.0,
                               double fps = 15.0) {
  auto ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::parseProfileKind(profile);
  so.profile.duration_s = duration_s;
  so.fps = fps;
  return so;
}

void expectLoopsOnEveryRevisit(const LoopRun& r) {
  EXPECT_EQ(r.wrong, 0u);
  for (int lap = 1; lap < r.laps; ++lap)
    EXPECT_TRUE(r.laps_with_loops.count(lap)) << "no loop closed during lap " << lap;
  EXPECT_LE(r.ate_final, 0.6 * r.ate_odometry);
  EXPECT_LE(r.ate_online, r.ate_odometry * 1.05);
}

}  // namespace

TEST(LoopAccuracy, WheeledCircle15HzOdometryBeatsMonocularByHalfAndALoopClosesOnEveryLap) {
  const LoopRun r = runLoops(profileOptions("wheeled_circle"), true);
  {
    SCOPED_TRACE("odometry (VIO criteria)");
    test::expectHealthyOdometry(r.odometry);
    EXPECT_LE(r.odometry.ate_posyaw, 0.04);
    EXPECT_LE(std::abs(r.odometry.scale - 1.0), 0.005);
    // A monocular run that never initialises counts as failed, so the comparison only needs it
    // to have produced a trajectory when it did.
    if (r.mono.evaluated) {
      EXPECT_LE(r.odometry.ate_posyaw, 0.5 * r.mono.ate_posyaw);
    }
  }
  SCOPED_TRACE("loop closure");
  ASSERT_GE(r.laps, 2);
  expectLoopsOnEveryRevisit(r);
}

TEST(LoopAccuracy, HandheldRoomTour30HzOdometryWithin2cmAndTheLoopClosesWhenItReturns) {
  // 2026-12-03: final 0.56 cm = 60 % of the odometry's 0.94 cm at 30 Hz (the criterion's limit:
  // the odometry got twice as good that day), 53 % at 15 Hz (doc/loop.md).
  const LoopRun r = runLoops(profileOptions("handheld", 0.0, 30.0));
  {
    SCOPED_TRACE("odometry (VIO criteria)");
    test::expectHealthyOdometry(r.odometry);
    EXPECT_LE(r.odometry.ate_posyaw, 0.02);
  }
  SCOPED_TRACE("loop closure");
  ASSERT_GE(r.laps, 1);
  EXPECT_GT(r.accepted, 0u);
  expectLoopsOnEveryRevisit(r);
}

TEST(LoopAccuracy, ASequenceThatNeverRevisitsAcceptsNoLoop) {
  const LoopRun r = runLoops(profileOptions("handheld", 12.0));
  EXPECT_EQ(r.laps, 0);
  EXPECT_EQ(r.accepted, 0u);
  EXPECT_DOUBLE_EQ(r.ate_final, r.ate_odometry);
}
