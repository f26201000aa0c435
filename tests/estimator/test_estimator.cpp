// Initialisation pieces and the whole sliding-window estimator on the analytic world (exact IMU,
// ideal feature tracks): known answers and accuracy bounds.
#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <unordered_map>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/initializer.h"
#include "rgbdi/estimator/sliding_window_estimator.h"
#include "rgbdi/imu/preintegration.h"
#include "synthetic_world.h"

using namespace rgbdi;
using namespace rgbdi::estimator;

TEST(Initializer, PnPRecoversLargeRotationAndRejectsOutliers) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T_curr_prev = Eigen::Isometry3d::Identity();
  // 70 degrees about a skew axis: an Rx*Ry*Rz composition of the rotation vector would be wrong.
  T_curr_prev.linear() = expSO3(Eigen::Vector3d(0.6, -0.8, 0.7).normalized() * 70.0 * M_PI / 180.0);
  T_curr_prev.translation() << 0.3, -0.1, 0.2;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> xn;
  for (int i = 0; i < 200; ++i) {
    // Points in front of the current camera, expressed in the previous one.
    const Eigen::Vector3d pc(u(rng) * 2, u(rng) * 1.5, 2.5 + u(rng));
    pts.push_back(T_curr_prev.inverse() * pc);
    Eigen::Vector2d x = pc.head<2>() / pc.z();
    if (i % 10 == 0) x += Eigen::Vector2d(0.05, -0.04);  // 10 % gross outliers
    xn.push_back(x);
  }
  PnpOptions opt;
  const auto res = relativePoseByPnP(pts, xn, opt);
  ASSERT_TRUE(res.has_value());
  EXPECT_EQ(res->inliers, 180);
  EXPECT_LT((res->T_curr_prev.translation() - T_curr_prev.translation()).norm(), 1e-6);
  EXPECT_LT(logSO3(res->T_curr_prev.rotation().transpose() * T_curr_prev.rotation()).norm(), 1e-6);
  // Too few inliers: rejected, not silently accepted.
  opt.min_inliers = 190;
  EXPECT_FALSE(relativePoseByPnP(pts, xn, opt).has_value());
}

TEST(Initializer, LinearAlignmentRecoversVelocitiesAndGravity) {
  test::SyntheticWorld w;
  ImuOptions imu_opt;
  imu::ImuNoise noise = imu::ImuNoise::fromOptions(imu_opt);
  std::vector<Eigen::Isometry3d> T;
  std::vector<std::unique_ptr<imu::Preintegration>> pre;
  std::vector<const imu::Preintegration*> pre_ptrs;
  // Express poses in an arbitrary reference frame (as vision would: first camera frame).
  Eigen::Isometry3d T_ref_world = Eigen::Isometry3d::Identity();
  T_ref_world.linear() = expSO3(Eigen::Vector3d(0.3, -1.0, 0.4));
  T_ref_world.translation() << 1, 2, 3;
  const double t0 = 4.0, dt_frame = 1.0 / 30.0;
  for (int k = 0; k < 10; ++k) {
    const double t = t0 + k * dt_frame;
    T.push_back(T_ref_world * w.pose(t));
    if (k == 0) {
      pre.emplace_back();
    } else {
      auto p = std::make_unique<imu::Preintegration>(Eigen::Vector3d::Zero(),
                                                     Eigen::Vector3d::Zero(), noise);
      for (double s = t - dt_frame; s <= t + 1e-9; s += dt_frame / 10) p->push(w.imu(s));
      pre.push_back(std::move(p));
    }
    pre_ptrs.push_back(pre.back().get());
  }
  const auto res = alignVelocitiesAndGravity(T, pre_ptrs, w.gravity);
  ASSERT_TRUE(res.has_value());
  const Eigen::Vector3d g_ref_true = T_ref_world.rotation() * Eigen::Vector3d(0, 0, -w.gravity);
  EXPECT_LT((res->g_ref - g_ref_true).norm(), 2e-3);
  for (int k = 0; k < 10; ++k) {
    const Eigen::Vector3d v_true = T_ref_world.rotation() * w.velocity(t0 + k * dt_frame);
    EXPECT_LT((res->v_ref[static_cast<size_t>(k)] - v_true).norm(), 2e-3) << k;
  }
}

namespace {

struct RunResult {
  double max_pos_err = 0.0;
  double final_pos_err = 0.0;
  int poses = 0;
  int resets = 0;
  double first_pose_t = -1;
  double last_reset_t = -1;  ///< [s from start] of the last reset
  double first_pose_after_reset_t = -1;
  double max_step = 0.0;  ///< [m] largest jump between consecutive output positions
  double final_time_offset = 0.0;
  double final_readout = 0.0;  ///< [s] rolling-shutter readout (configured or estimated)
  EstimatorStats stats;
};

/// Options of a synthetic run besides the estimator's own.
struct RunSetup {
  double duration = 12.0;    ///< [s]
  double depth_sigma = 0.0;  ///< depth noise coefficient (sigma = c z^2)
  double start_t = 0.0;      ///< [s] where the stream starts on the world's trajectory
  double pixel_sigma = 0.0;  ///< [px] tracking noise
  double time_offset = 0.0;  ///< [s] true camera-IMU offset: images stamped t_imu - offset
  std::uint64_t noise_seed = 1;
  bool with_depth = true;      ///< false: no feature has a depth (the --no-depth mode)
  double cam_dt = 1.0 / 30.0;  ///< [s] between images
  double readout_s = 0.0;      ///< [s] true rolling-shutter readout (480 rows, top to bottom)
  double configured_readout_s = 0.0;  ///< [s] the estimator's (its prior when it estimates it)
  /// Optional corruption of the IMU stream (fault injection).
  std::function<void(ImuSample&)> imu_fault = {};
};

/// Feeds the analytic world into the estimator; compares each causal pose with the truth after
/// anchoring the first estimated pose to the true one (position + yaw: the unobservable DOF).
RunResult runSynthetic(const RunSetup& setup,
                       const std::function<void(EstimatorOptions&)>& tweak = {}) {
  const double start_t = setup.start_t;
  test::SyntheticWorld w;
  ExtrinsicOptions ext;
  w.T_bc = ext.T_body_cam;
  w.makeLandmarks(5, 1500);
  ImuOptions imu_opt;
  imu_opt.gravity_m_s2 = w.gravity;
  EstimatorOptions opt;
  opt.estimate_time_offset = false;
  if (tweak) tweak(opt);
  SlidingWindowEstimator est(opt, imu_opt, ext);
  if (setup.configured_readout_s > 0.0 || opt.estimate_rolling_shutter_readout) {
    RollingShutter rs;
    rs.readout_s = setup.configured_readout_s;
    rs.rows = 480;
    est.setRollingShutter(rs);
  }
  std::mt19937_64 rng(setup.noise_seed);
  RunResult r;
  const double imu_dt = 1.0 / 200.0, cam_dt = setup.cam_dt;
  double t_imu = start_t;
  bool anchored = false;
  Eigen::Isometry3d T_align = Eigen::Isometry3d::Identity();
  std::uint64_t index = 0;
  std::unordered_map<std::uint64_t, Eigen::Vector2d> previous_xn;
  Eigen::Vector3d last_p = Eigen::Vector3d::Zero();
  for (double t_cam = start_t + 0.1; t_cam < start_t + setup.duration; t_cam += cam_dt) {
    // The estimator may look ahead by its current offset estimate: feed IMU well past the image.
    while (t_imu <= t_cam + 0.05) {
      ImuSample m = w.imu(t_imu);
      if (setup.imu_fault) setup.imu_fault(m);
      est.feedImu(m);
      t_imu += imu_dt;
    }
    // The image shows the scene at IMU time t_cam, but is stamped t_cam - offset.
    frontend::FeatureFrame frame =
        w.observe(t_cam, index++, setup.depth_sigma, rng, setup.pixel_sigma, setup.readout_s);
    frame.t = t_cam - setup.time_offset;
    if (!setup.with_depth)
      for (auto& f : frame.features) f.depth_m = 0.0;
    // Image-plane velocity by backward difference, as the front end computes it.
    std::unordered_map<std::uint64_t, Eigen::Vector2d> current_xn;
    for (auto& f : frame.features) {
      const auto it = previous_xn.find(f.id);
      if (it != previous_xn.end()) f.velocity_xn = (f.xn - it->second) / cam_dt;
      current_xn[f.id] = f.xn;
    }
    previous_xn.swap(current_xn);
    const FrameEstimate e = est.processFrame(frame);
    if (e.reset) {
      ++r.resets;
      r.last_reset_t = t_cam - start_t;
      r.first_pose_after_reset_t = -1;
    }
    if (!e.has_pose) continue;
    if (r.resets > 0 && r.first_pose_after_reset_t < 0)
      r.first_pose_after_reset_t = t_cam - start_t;
    if (r.poses > 0)
      r.max_step = std::max(r.max_step, (e.T_world_body.translation() - last_p).norm());
    last_p = e.T_world_body.translation();
    if (r.first_pose_t < 0) r.first_pose_t = t_cam - start_t;
    const Eigen::Isometry3d T_true = w.pose(e.t_imu);
    if (!anchored) {
      // Position + yaw anchor (roll and pitch are observable and must not be corrected).
      const double dyaw = yawOf(T_true.rotation()) - yawOf(e.T_world_body.rotation());
      T_align.linear() = Eigen::AngleAxisd(dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      T_align.translation() =
          T_true.translation() - T_align.linear() * e.T_world_body.translation();
      anchored = true;
    }
    const double err = ((T_align * e.T_world_body).translation() - T_true.translation()).norm();
    r.max_pos_err = std::max(r.max_pos_err, err);
    r.final_pos_err = err;
    r.final_time_offset = e.time_offset_s;
    r.final_readout = e.rolling_shutter_readout_s;
    ++r.poses;
  }
  r.stats = est.stats();
  return r;
}

}  // namespace

TEST(SlidingWindowEstimator, StaticStartExactDataTracksToMillimetres) {
  const RunResult r = runSynthetic({12.0, 0.0, 0.0, 0.0});
  EXPECT_EQ(r.resets, 0);
  EXPECT_LT(r.first_pose_t, 0.5);  // static initialisation right at the start
  EXPECT_GT(r.poses, 330);
  EXPECT_LT(r.max_pos_err, 0.01) << "final " << r.final_pos_err;
}

TEST(SlidingWindowEstimator, MovingStartInitialisesWithinOneSecond) {
  // Start the stream while moving at full speed: the depth-aided PnP initialisation must take over.
  const RunResult r = runSynthetic({8.0, 0.0, 6.0, 0.0});
  EXPECT_EQ(r.resets, 0);
  EXPECT_GE(r.first_pose_t, 0.0);
  EXPECT_LT(r.first_pose_t, 1.0);
  EXPECT_LT(r.max_pos_err, 0.02) << "final " << r.final_pos_err;
}

TEST(SlidingWindowEstimator, ImagesFarApartStillStartAtRestAndInMotion) {
  // Images 0.3 s apart (a 3 Hz camera, or a live run dropping two of every three images): the
  // stillness test must judge the time since the previous image (no two images lie within its
  // 0.2 s window), and the moving start must accept the alignment residual that the unknown
  // accelerometer bias leaves over 0.3 s (0.006-0.010 on clean data, gate 0.005 at 0.1 s).
  RunSetup at_rest{8.0, 0.0, 0.0, 0.0};
  at_rest.cam_dt = 0.3;
  const RunResult r = runSynthetic(at_rest);
  EXPECT_EQ(r.stats.static_initialisations, 1);
  EXPECT_EQ(r.resets, 0);
  EXPECT_GE(r.first_pose_t, 0.0);
  EXPECT_LT(r.first_pose_t, 0.5);  // the second image
  EXPECT_LT(r.max_pos_err, 0.02) << "final " << r.final_pos_err;

  // Moving: an accelerometer bias at the edge of rgbdi-sim's range (0.1 m/s^2 per axis), white
  // noise at its default levels (0.02 m/s^2 and 0.002 rad/s per sqrt(Hz) at 200 Hz), depth and
  // pixel noise.
  RunSetup moving{10.0, 0.004, 6.0, 0.5};
  moving.cam_dt = 0.3;
  const Eigen::Vector3d acc_bias(0.1, -0.1, 0.1);  // [m/s^2], within the simulator's range
  auto rng = std::make_shared<std::mt19937_64>(5);
  moving.imu_fault = [acc_bias, rng](ImuSample& m) {
    std::normal_distribution<double> n01(0.0, 1.0);
    const double sqrt_rate = std::sqrt(200.0);
    for (int i = 0; i < 3; ++i) {
      m.acc[i] += acc_bias[i] + 0.02 * sqrt_rate * n01(*rng);
      m.gyr[i] += 0.002 * sqrt_rate * n01(*rng);
    }
  };
  // A full window (3 s) before the first attempt, as after the wheeled robot's slow start in
  // the live run where this was seen: alignment residual 0.007 here.
  const RunResult m =
      runSynthetic(moving, [](EstimatorOptions& o) { o.init_min_parallax_px = 1e4; });
  EXPECT_EQ(m.stats.moving_initialisations, 1);
  EXPECT_EQ(m.resets, 0);
  EXPECT_GE(m.first_pose_t, 0.0);
  EXPECT_LT(m.first_pose_t, 3.0);  // window_size = 10 images: 2.8 s
  EXPECT_LT(m.max_pos_err, 0.05) << "final " << m.final_pos_err;
  std::cout << "at rest: first pose " << r.first_pose_t << " s, max error " << r.max_pos_err
            << " m; moving: first pose " << m.first_pose_t << " s, max error " << m.max_pos_err
            << " m\n";
}

TEST(SlidingWindowEstimator, MovingStartWithoutDepthInitialisesByVisualSfm) {
  // No depth at all and already moving: only the visual SfM + scale alignment can start.
  RunSetup setup{10.0, 0.0, 1.0, 0.5};
  setup.with_depth = false;
  const RunResult r = runSynthetic(setup);
  std::cout << "first pose " << r.first_pose_t << " s, max error " << r.max_pos_err << " m, final "
            << r.final_pos_err << " m\n";
  EXPECT_EQ(r.resets, 0);
  EXPECT_GE(r.first_pose_t, 0.0);
  EXPECT_LT(r.first_pose_t, 3.0);
  EXPECT_EQ(r.stats.visual_initialisations, 1);
  EXPECT_EQ(r.stats.static_initialisations, 0);
  EXPECT_LT(r.max_pos_err, 0.2);
}

TEST(SlidingWindowEstimator, WithoutDepthAtConstantSpeedTheScaleIsNotGuessed) {
  // Steady circling: the body-frame acceleration is constant, which the alignment cannot tell
  // from a gravity tilt, so the scale is unobservable; the estimator must keep waiting.
  RunSetup setup{4.0, 0.0, 3.0, 0.5};
  setup.with_depth = false;
  const RunResult r = runSynthetic(setup);
  EXPECT_EQ(r.poses, 0);
  EXPECT_EQ(r.stats.moving_initialisations, 0);
}

TEST(SlidingWindowEstimator, EveryFrameWaitingForAStartCountsTheReasonOfEachStart) {
  // The no-depth constant-speed run above never starts: each frame tries the static start (the
  // sensor turns: no stillness) and the moving start (no depth: visual SfM, whose scale is not
  // observable). Both reasons are counted on every frame, so a run that ends without a pose
  // can say why.
  RunSetup setup{4.0, 0.0, 3.0, 0.5};
  setup.with_depth = false;
  const RunResult r = runSynthetic(setup);
  ASSERT_EQ(r.poses, 0);
  for (const auto& [reason, n] : r.stats.init_waits) std::cout << n << "  " << reason << "\n";
  int static_waits = 0, moving_waits = 0;
  for (const auto& [reason, n] : r.stats.init_waits) {
    if (reason.rfind("static start: ", 0) == 0) static_waits += n;
    if (reason.rfind("moving start: ", 0) == 0) moving_waits += n;
  }
  EXPECT_EQ(static_waits, r.stats.frames);
  EXPECT_EQ(moving_waits, r.stats.frames);
  // The window fills first (window_size 10 keyframes: at least 9 frames collect), then every
  // SfM + alignment fails on the scale; nothing else.
  const auto waits = [&r](const std::string& reason) {
    const auto it = r.stats.init_waits.find(reason);
    return it == r.stats.init_waits.end() ? 0 : it->second;
  };
  const int collecting = waits("moving start: collecting frames for a visual (SfM) initialisation");
  EXPECT_GE(collecting, 9);
  EXPECT_EQ(collecting + waits("moving start: scale/gravity alignment failed or the scale is not "
                               "observable yet"),
            r.stats.frames);
  EXPECT_EQ(waits("static start: gyro mean above init_static_max_gyro_rad_s") +
                waits("static start: not enough IMU history for the stillness test"),
            r.stats.frames);
}

TEST(SlidingWindowEstimator, NoisyDepthAndPixelsStayAccurateInBothDepthModes) {
  // D435-like depth noise (0.004 z^2) and 0.5 px tracking noise; 12 s, about 4 m travelled.
  for (const char* mode : {"constant", "prior"}) {
    const RunResult r = runSynthetic({12.0, 0.004, 0.0, 0.5},
                                     [&](EstimatorOptions& o) { o.verified_depth = mode; });
    std::cout << mode << ": max error " << r.max_pos_err << " m, final " << r.final_pos_err
              << " m\n";
    EXPECT_EQ(r.resets, 0) << mode;
    EXPECT_LT(r.max_pos_err, 0.02) << mode;
    EXPECT_LT(r.final_pos_err, 0.01) << mode;
  }
}

TEST(SlidingWindowEstimator, TimeOffsetConvergesToTheTrueValue) {
  // Images stamped `offset` before the IMU time they show; the estimator starts from 0. Exact
  // feature positions (the depth is noisy) isolate the estimator's own offset model. This world
  // turns slowly (0.2 rad/s), so the offset is weakly observable: a weak prior lets the data
  // decide (the default prior is tuned for real motion; the end-to-end test covers it).
  for (double true_offset : {0.010, 0.0, -0.008}) {
    const RunResult r = runSynthetic({16.0, 0.004, 0.0, 0.0, true_offset}, [](EstimatorOptions& o) {
      o.estimate_time_offset = true;
      o.time_offset_prior_sigma_s = 0.02;
    });
    EXPECT_EQ(r.resets, 0) << true_offset;
    EXPECT_NEAR(r.final_time_offset, true_offset, 0.001);
    EXPECT_LT(r.max_pos_err, 0.005) << true_offset;
  }
}

TEST(SlidingWindowEstimator, RollingShutterReadoutIsEstimatedFromAWrongPrior) {
  // A 33 ms readout; the estimator starts from 0 or 10 ms (the prior's mean) and estimates it
  // with the time offset, as a parameter of the window's reprojections.
  RunSetup setup{16.0, 0.004, 0.0, 0.0, 0.004};
  setup.readout_s = 0.033;
  for (double configured : {0.0, 0.010}) {
    setup.configured_readout_s = configured;
    const RunResult r = runSynthetic(setup, [](EstimatorOptions& o) {
      o.estimate_time_offset = true;
      o.time_offset_prior_sigma_s = 0.02;
      o.estimate_rolling_shutter_readout = true;
    });
    std::cout << "started from " << 1e3 * configured << " ms: readout " << 1e3 * r.final_readout
              << " ms, time offset " << 1e3 * r.final_time_offset << " ms, max error "
              << r.max_pos_err << " m\n";
    EXPECT_EQ(r.resets, 0) << configured;
    EXPECT_NEAR(r.final_readout, 0.033, 0.003) << configured;
    EXPECT_NEAR(r.final_time_offset, 0.004, 0.002) << configured;
    EXPECT_LT(r.max_pos_err, 0.01) << configured;
  }
}

TEST(SlidingWindowEstimator, RollingShutterCompensationNeedsTheReadout) {
  // The same 33 ms readout with the readout known (compensated at window entry), not
  // compensated, and estimated from 0: the compensated runs track as well as a global shutter.
  RunSetup setup{16.0, 0.004, 0.0, 0.0, 0.0};
  const RunResult global = runSynthetic(setup);
  setup.readout_s = 0.033;
  const RunResult ignored = runSynthetic(setup);
  setup.configured_readout_s = 0.033;
  const RunResult known = runSynthetic(setup);
  setup.configured_readout_s = 0.0;
  const RunResult estimated =
      runSynthetic(setup, [](EstimatorOptions& o) { o.estimate_rolling_shutter_readout = true; });
  std::cout << "final position error: global " << global.final_pos_err << " m, ignored "
            << ignored.final_pos_err << " m, known " << known.final_pos_err << " m, estimated "
            << estimated.final_pos_err << " m (" << 1e3 * estimated.final_readout << " ms)\n";
  EXPECT_EQ(known.final_readout, 0.033);
  EXPECT_LT(known.final_pos_err, 2.0 * global.final_pos_err + 0.002);
  EXPECT_LT(estimated.final_pos_err, 2.0 * global.final_pos_err + 0.002);
  EXPECT_NEAR(estimated.final_readout, 0.033, 0.003);
}

TEST(SlidingWindowEstimator, ReadoutEstimateStaysWithinItsBoundsOnAGlobalShutter) {
  // No readout to find: started from 10 ms, the estimate stays within [0, max] and near 0.
  RunSetup setup{16.0, 0.004, 0.0, 0.5, 0.0};
  setup.configured_readout_s = 0.010;
  const RunResult r = runSynthetic(setup, [](EstimatorOptions& o) {
    o.estimate_rolling_shutter_readout = true;
    o.rolling_shutter_readout_max_s = 0.05;
  });
  EXPECT_EQ(r.resets, 0);
  EXPECT_GE(r.final_readout, 0.0);
  EXPECT_LE(r.final_readout, 0.05);
  EXPECT_LT(r.final_readout, 0.003);
}

TEST(SlidingWindowEstimator, MotionFieldVelocityKeepsPixelNoiseOutOfTheTimeOffset) {
  // With white tracking noise, velocities from differenced positions correlate with the positions
  // and the offset absorbs the noise (the reference implementation's model); the motion field
  // does not. Measured: tracked 61 ms, motion field 8 ms for a true 0 (0.5 px noise).
  double error[2];
  int k = 0;
  for (const char* mode : {"tracked", "motion_field"}) {
    const RunResult r = runSynthetic({16.0, 0.004, 0.0, 0.5, 0.0}, [&](EstimatorOptions& o) {
      o.estimate_time_offset = true;
      o.time_offset_velocity = mode;
    });
    std::cout << mode << ": time offset " << 1000.0 * r.final_time_offset << " ms, max error "
              << r.max_pos_err << " m\n";
    error[k++] = std::abs(r.final_time_offset);
  }
  EXPECT_LT(error[1], 0.25 * error[0]);
  EXPECT_LT(error[1], 0.012);
}

TEST(SlidingWindowEstimator, FailureIsDetectedAndTheTrajectoryContinues) {
  // A 0.4 s accelerometer fault (a shock saturating one axis) at 6 s: the IMU and vision
  // disagree, the estimate breaks, the failure is detected, and the estimator re-initialises from
  // the last good pose so the output trajectory stays continuous.
  RunSetup setup{12.0, 0.004, 0.0, 0.5};
  setup.imu_fault = [](ImuSample& m) {
    if (m.t > 6.0 && m.t < 6.4) m.acc.x() += 60.0;
  };
  const RunResult r = runSynthetic(setup);
  std::cout << "resets " << r.resets << " (last at " << r.last_reset_t << " s), first pose after "
            << r.first_pose_after_reset_t << " s, max step " << r.max_step << " m, max error "
            << r.max_pos_err << " m, final " << r.final_pos_err << " m\n";
  EXPECT_GE(r.resets, 1);
  EXPECT_GT(r.last_reset_t, 6.0);
  EXPECT_LT(r.last_reset_t, 7.0);
  EXPECT_GT(r.first_pose_after_reset_t, r.last_reset_t);
  EXPECT_LT(r.first_pose_after_reset_t, r.last_reset_t + 1.0);
  // Continuity: the restarted trajectory continues from the last pose (the platform moves about
  // 0.25 m while the estimator re-initialises; that is the largest step allowed).
  EXPECT_LT(r.max_step, 0.25);
  EXPECT_LT(r.max_pos_err, 0.3);
  EXPECT_LT(r.final_pos_err, 0.2);
}

TEST(SlidingWindowEstimator, TheEarlyStopAppliesOnlyWhenTheWindowHasDepthVerifiedFeatures) {
  // With depth: solver_function_tolerance (1e-3) stops earlier than Ceres' default 1e-6, with
  // the same accuracy.
  const RunSetup noisy{6.0, 0.004, 0.0, 0.5};
  const RunResult early = runSynthetic(noisy);
  const RunResult full =
      runSynthetic(noisy, [](EstimatorOptions& o) { o.solver_function_tolerance = 1e-6; });
  ASSERT_EQ(early.stats.optimisations, full.stats.optimisations);
  EXPECT_LT(early.stats.solver_iterations, full.stats.solver_iterations);
  EXPECT_EQ(early.resets, 0);
  EXPECT_LT(early.max_pos_err, 0.02);
  EXPECT_LT(early.final_pos_err, 0.01);

  // Without depth nothing is depth-verified: solver_function_tolerance is not used at all (the
  // same run to the last bit), solver_function_tolerance_no_depth is.
  RunSetup mono{6.0, 0.0, 1.0, 0.5};
  mono.with_depth = false;
  const RunResult base = runSynthetic(mono);
  const RunResult ignored =
      runSynthetic(mono, [](EstimatorOptions& o) { o.solver_function_tolerance = 0.1; });
  const RunResult loose =
      runSynthetic(mono, [](EstimatorOptions& o) { o.solver_function_tolerance_no_depth = 0.1; });
  ASSERT_GT(base.stats.optimisations, 50);
  EXPECT_EQ(ignored.stats.solver_iterations, base.stats.solver_iterations);
  EXPECT_EQ(ignored.final_pos_err, base.final_pos_err);
  EXPECT_LT(loose.stats.solver_iterations, base.stats.solver_iterations);
}

TEST(SlidingWindowEstimator, NonKeyframeUpdatesTakeOneStepAndKeepTheAccuracy) {
  // Updates whose second-newest frame is no keyframe (it leaves the window afterwards) take one
  // solver iteration with "single_step"; "full" solves every update to convergence.
  const RunSetup noisy{6.0, 0.004, 0.0, 0.5};
  const RunResult single = runSynthetic(noisy);  // the default
  const RunResult full =
      runSynthetic(noisy, [](EstimatorOptions& o) { o.non_keyframe_update = "full"; });
  EXPECT_EQ(full.stats.single_step_updates, 0);
  ASSERT_GT(single.stats.single_step_updates, 10);
  ASSERT_EQ(single.stats.optimisations, full.stats.optimisations);
  EXPECT_LT(single.stats.solver_iterations, full.stats.solver_iterations);
  EXPECT_EQ(single.resets, 0);
  EXPECT_LT(single.max_pos_err, 0.02);
  EXPECT_LT(single.final_pos_err, 0.01);

  // Without depth-verified features every update is a full one: the same run to the last bit.
  RunSetup mono{6.0, 0.0, 1.0, 0.5};
  mono.with_depth = false;
  const RunResult mono_single = runSynthetic(mono);
  const RunResult mono_full =
      runSynthetic(mono, [](EstimatorOptions& o) { o.non_keyframe_update = "full"; });
  ASSERT_GT(mono_single.stats.optimisations, 50);
  EXPECT_EQ(mono_single.stats.single_step_updates, 0);
  EXPECT_EQ(mono_single.stats.solver_iterations, mono_full.stats.solver_iterations);
  EXPECT_EQ(mono_single.final_pos_err, mono_full.final_pos_err);
}
