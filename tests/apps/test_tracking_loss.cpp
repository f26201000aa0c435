// Relocalisation after a tracking loss within a run (issue 12, point 3): seconds of black frames
// (the simulator's blackout: black colour, no depth) make the odometry lose tracking and
// re-initialise in a frame of its own; the new segment is reconnected to the earlier map by the
// first verified match, and the run ends with one continuous trajectory in one world frame
// whose ATE is within 20 % of the same run without the loss. The gap is reported, never
// bridged with made-up poses.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "rgbdi/common/fan_out_sink.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi {
namespace {

/// Frames exposed in [t0, t1) (camera clock) reach the target as the simulator's blackout
/// renders them: black colour, depth 0. Lets one rendering feed a run with and one without loss.
class BlackoutFilter : public MeasurementSink {
 public:
  BlackoutFilter(MeasurementSink& target, double t0, double t1)
      : target_(target), t0_(t0), t1_(t1) {}
  void feedImu(const ImuSample& imu) override { target_.feedImu(imu); }
  void feedRgbd(const RgbdFrame& frame) override {
    if (frame.t < t0_ || frame.t >= t1_) return target_.feedRgbd(frame);
    RgbdFrame black = frame;
    black.rgb = cv::Mat::zeros(frame.rgb.size(), frame.rgb.type());
    black.depth = cv::Mat::zeros(frame.depth.size(), frame.depth.type());
    target_.feedRgbd(black);
  }
  void endOfStream() override { target_.endOfStream(); }

 private:
  MeasurementSink& target_;
  double t0_, t1_;
};

double ate(const Trajectory& gt, const Trajectory& est) {
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  return eval::evaluate(gt, est, eo).ate.rmse;
}

/// The wheeled robot's circle at 0.8 m/s (a 16 s lap), 30 s at 15 Hz.
sim::SimOptions fastCircle() {
  auto sim_ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(sim_ini);
  so.profile.kind = sim::ProfileKind::WheeledCircle;
  so.profile.speed_m_s = 0.8;
  so.profile.duration_s = 30.0;
  so.fps = 15.0;
  return so;
}

system::SystemConfig configOf(const sim::SimulatedSequence& seq) {
  auto ini = IniReader::fromText(sim::slamConfigText(seq), "generated config.ini");
  return system::SystemConfig::load(ini);
}

/// The poses of `tr` stamped in [t0, t1).
Trajectory part(const Trajectory& tr, double t0, double t1) {
  Trajectory out;
  for (const StampedPose& p : tr)
    if (p.t >= t0 && p.t < t1) out.push_back(p);
  return out;
}

TEST(TrackingLoss, ThreeSecondsOfBlackFramesEndInOneContinuousTrajectory) {
  // The wheeled robot's circle at 0.8 m/s: a 16 s lap, so the blackout in the second lap ends
  // where the first lap has mapped.
  const sim::SimulatedSequence seq(fastCircle());
  const system::SystemConfig cfg = configOf(seq);
  const double t_black = seq.frameStamp(0) + 19.0, t_light = t_black + 3.0;

  system::SlamSystem clean(cfg, {}), lossy(cfg, {});
  BlackoutFilter blackout(lossy, t_black, t_light);
  FanOutSink both({&clean, &blackout});
  seq.pump(both);

  // The loss was detected (no features) and the odometry re-initialised once: two segments.
  EXPECT_EQ(clean.odometry().estimatorStats().resets, 0);
  EXPECT_EQ(lossy.odometry().estimatorStats().blind_resets, 1);
  EXPECT_EQ(lossy.odometry().estimatorStats().resets, 1);
  // The new segment was joined to the first by a verified match, soon after the light returned.
  ASSERT_NE(lossy.loopCloser(), nullptr);
  ASSERT_EQ(lossy.loopCloser()->joins().size(), 1u);
  const loop::JoinRecord& j = lossy.loopCloser()->joins().front();
  EXPECT_EQ(j.segment, 1);
  EXPECT_EQ(j.to_segment, 0);
  EXPECT_TRUE(lossy.segmentInOrigin(1));
  std::cout << "reconnected on the view " << j.t_query - t_light << " s after the blackout"
            << std::endl;
  EXPECT_LE(j.t_query - t_light, 3.0);

  // One trajectory, none of it made up in the gap: the odometry has IMU-only poses for the blind
  // second before its reset (at most fail_max_blind_s into the blackout), the final trajectory
  // leaves them out (dead reckoning the estimator gave up on) and has every other frame.
  const Trajectory fin = lossy.finalTrajectory();
  const Trajectory odo = lossy.odometryTrajectory();
  const double t_reset = t_black + cfg.estimator.fail_max_blind_s + 0.2;
  std::size_t blind_odometry = 0;
  for (const StampedPose& p : odo) blind_odometry += p.t >= t_black && p.t < t_reset ? 1 : 0;
  EXPECT_GE(blind_odometry, 10u);
  for (const StampedPose& p : odo) EXPECT_FALSE(p.t > t_reset && p.t < t_light) << p.t;
  for (const StampedPose& p : fin) EXPECT_FALSE(p.t >= t_black && p.t < t_light) << p.t;
  EXPECT_EQ(fin.size() + blind_odometry, odo.size());
  EXPECT_LT(fin.size(), clean.finalTrajectory().size());
  // The camera-frame twin follows the kept poses with their image stamps.
  const Trajectory fin_cam = lossy.toCameraFrame(fin);
  ASSERT_EQ(fin_cam.size(), fin.size());
  const Trajectory odo_cam = lossy.toCameraFrame(odo);
  std::size_t k = 0;
  for (std::size_t i = 0; i < fin.size(); ++i) {
    while (k < odo.size() && odo[k].t < fin[i].t) ++k;
    ASSERT_LT(k, odo.size());
    EXPECT_EQ(fin_cam[i].t, odo_cam[k].t) << i;  // the same frame's image stamp
  }

  const Trajectory gt = seq.bodyTrajectory();
  const double ate_clean = ate(gt, clean.finalTrajectory());
  const double ate_lossy = ate(gt, fin);
  std::cout << "final ATE without the loss " << ate_clean << " m, with it " << ate_lossy
            << " m; odometry with the loss (two frames, one alignment) " << ate(gt, odo) << " m"
            << std::endl;
  // Where the difference is: each part of both runs on its own (own alignment).
  const Trajectory& cfin = clean.finalTrajectory();
  std::cout << "before the blackout: clean " << ate(gt, part(cfin, 0, t_black)) << " m, lossy "
            << ate(gt, part(fin, 0, t_black)) << " m; after it: clean "
            << ate(gt, part(cfin, t_light, 1e18)) << " m, lossy "
            << ate(gt, part(fin, t_light, 1e18)) << " m" << std::endl;
  EXPECT_LE(ate_lossy, 1.2 * ate_clean);
}

TEST(TrackingLoss, TwoSecondsOfBlackFramesAreBridgedByTheImu) {
  // Issue 14 point 2: a blackout of up to fail_max_blind_s (2 s) is carried by the IMU, with no
  // reset: the window keeps the frames that saw, the first frame seen again continues it, the
  // pose graph trusts the IMU-only stretch as little as it deserves and the final trajectory
  // spreads the correction over the blind frames. Every frame keeps a pose.
  const sim::SimulatedSequence seq(fastCircle());
  const system::SystemConfig cfg = configOf(seq);
  ASSERT_GE(cfg.estimator.fail_max_blind_s, 2.0);
  // Frames exposed in [t_black, t_light): 30 black frames, 1.93 s from the first to the last.
  const double t_black = seq.frameStamp(0) + 19.0, t_light = t_black + 2.0;

  system::SlamSystem clean(cfg, {}), lossy(cfg, {});
  BlackoutFilter blackout(lossy, t_black, t_light);
  FanOutSink both({&clean, &blackout});
  seq.pump(both);

  EXPECT_EQ(clean.odometry().estimatorStats().resets, 0);
  EXPECT_EQ(lossy.odometry().estimatorStats().resets, 0);
  EXPECT_EQ(lossy.odometry().estimatorStats().blind_resets, 0);
  const Trajectory fin = lossy.finalTrajectory();
  const Trajectory odo = lossy.odometryTrajectory();
  ASSERT_EQ(fin.size(), clean.finalTrajectory().size());  // no frame without a pose
  ASSERT_EQ(odo.size(), fin.size());
  std::size_t blind = 0;
  for (const StampedPose& p : odo) blind += p.t >= t_black && p.t < t_light ? 1 : 0;
  EXPECT_GE(blind, 29u);

  const Trajectory gt = seq.bodyTrajectory();
  const double ate_clean = ate(gt, clean.finalTrajectory());
  const double ate_lossy = ate(gt, fin);
  const double ate_odometry = ate(gt, odo);
  // The blind frames' error under the whole run's alignment.
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  const eval::Alignment al = eval::evaluate(gt, fin, eo).alignment;
  double blind_sq = 0.0;
  std::size_t blind_n = 0;
  std::size_t g = 0;
  for (const StampedPose& p : fin) {
    if (p.t < t_black || p.t >= t_light) continue;
    while (g + 1 < gt.size() && std::abs(gt[g + 1].t - p.t) <= std::abs(gt[g].t - p.t)) ++g;
    blind_sq += (al.apply(p.p) - gt[g].p).squaredNorm();
    ++blind_n;
  }
  ASSERT_GT(blind_n, 0u);
  const double blind_rms = std::sqrt(blind_sq / static_cast<double>(blind_n));
  std::cout << "final ATE without the blackout " << ate_clean << " m, with it " << ate_lossy
            << " m (odometry " << ate_odometry << " m); the blind frames " << blind_rms
            << " m; after the blackout alone " << ate(gt, part(fin, t_light, 1e18)) << " m"
            << std::endl;
  EXPECT_LE(ate_lossy, 2.0 * ate_clean);
  EXPECT_LE(blind_rms, 0.04);
  EXPECT_LE(ate_odometry, 0.06);  // one continuous odometry through the blackout (two frames: ~1 m)
}

TEST(TrackingLoss, AFullTurnInTwoSecondsKeepsTrackingWithTheGyroscopesPrediction) {
  // Issue 14 point 2, extreme rotation: one whole turn about the vertical in 2 s on top of the
  // 0.8 m/s circle (peak 6.9 rad/s: 26 degrees between frames at 15 Hz, features move ~280 px,
  // beyond KLT's pyramid). The front end starts KLT where the gyroscope's rotation moves each
  // feature, so tracking goes on through the turn: no reset, a pose for every frame.
  sim::SimOptions so = fastCircle();
  so.spin_start_s = 19.0;
  so.spin_duration_s = 2.0;
  so.spin_turns = 1.0;
  const sim::SimulatedSequence seq(so);
  const system::SystemConfig cfg = configOf(seq);
  ASSERT_TRUE(cfg.frontend.klt_predict_rotation);
  system::SlamSystem run(cfg, {});
  seq.pump(run);

  EXPECT_EQ(run.odometry().estimatorStats().resets, 0);
  const Trajectory fin = run.finalTrajectory(), odo = run.odometryTrajectory();
  ASSERT_FALSE(fin.empty());
  // No gap: every frame from the first pose to the last has one, and the last is at the end (the
  // stream's final image may wait for IMU that never comes).
  std::size_t frames_in_span = 0;
  for (std::size_t i = 0; i < seq.frameCount(); ++i)
    frames_in_span += seq.frameStamp(i) >= fin.front().t && seq.frameStamp(i) <= fin.back().t;
  EXPECT_EQ(fin.size(), frames_in_span);
  EXPECT_GE(fin.back().t, seq.frameStamp(seq.frameCount() - 2));

  const Trajectory gt = seq.bodyTrajectory();
  const double t_spin = seq.frameStamp(0) + so.spin_start_s;
  const double ate_final = ate(gt, fin), ate_odometry = ate(gt, odo);
  std::cout << "final ATE " << ate_final << " m, odometry " << ate_odometry
            << " m; before the turn " << ate(gt, part(fin, 0.0, t_spin)) << " m, after it "
            << ate(gt, part(fin, t_spin + so.spin_duration_s, 1e18)) << " m" << std::endl;
  // Measured 5.8 / 12.6 mm (the clean 0.8 m/s circle: ~5 / ~10 mm).
  EXPECT_LE(ate_final, 0.01);
  EXPECT_LE(ate_odometry, 0.02);
}

}  // namespace
}  // namespace rgbdi
