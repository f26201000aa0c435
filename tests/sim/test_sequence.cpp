// SimulatedSequence: the push stream (order, counts, stop), time offset, determinism, ground
// truth API, options loading, and the scenes' structure along every profile's path.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "rgbdi/common/so3.h"
#include "rgbdi/sim/sequence.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

/// A short sequence: 9 s of wheeled_circle (the shortest allowed) at 5 frames/s.
SimOptions shortOptions(double time_offset = 0.0) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.fps = 5.0;
  o.time_offset_s = time_offset;
  return o;
}

struct Recorder : MeasurementSink {
  std::vector<double> stamps;
  std::vector<bool> is_frame;
  std::vector<ImuSample> imu;
  std::vector<RgbdFrame> frames;
  int ends = 0;
  std::atomic<bool>* stop_flag = nullptr;
  std::size_t stop_after = 0;

  void feedImu(const ImuSample& s) override {
    stamps.push_back(s.t);
    is_frame.push_back(false);
    imu.push_back(s);
    check();
  }
  void feedRgbd(const RgbdFrame& f) override {
    stamps.push_back(f.t);
    is_frame.push_back(true);
    frames.push_back(f);
    check();
  }
  void endOfStream() override { ++ends; }
  void check() {
    if (stop_flag && stamps.size() == stop_after) stop_flag->store(true);
  }
};

TEST(SimulatedSequence, PumpDeliversEverythingInTimeOrder) {
  const SimulatedSequence seq(shortOptions(0.02));
  EXPECT_EQ(seq.imuCount(), 1801u);  // 9 s at 200 Hz, both ends included
  EXPECT_EQ(seq.frameCount(), 46u);  // 9 s at 5 Hz
  Recorder rec;
  seq.pump(rec);
  EXPECT_EQ(rec.ends, 1);
  ASSERT_EQ(rec.imu.size(), seq.imuCount());
  ASSERT_EQ(rec.frames.size(), seq.frameCount());
  for (std::size_t j = 1; j < rec.stamps.size(); ++j)
    ASSERT_LE(rec.stamps[j - 1], rec.stamps[j]) << j;
  for (std::size_t k = 0; k < rec.imu.size(); ++k)
    EXPECT_DOUBLE_EQ(rec.imu[k].t, 1000.0 + k / 200.0);
  const PinholeCamera cam = CameraOptions().camera;
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    const RgbdFrame& f = rec.frames[i];
    EXPECT_EQ(f.index, i);
    // t_cam = t_imu - offset: the image exposed at IMU time 1000 + i/5 is stamped 20 ms earlier.
    EXPECT_DOUBLE_EQ(f.t, 1000.0 + i / 5.0 - 0.02);
    EXPECT_EQ(f.rgb.type(), CV_8UC3);
    EXPECT_EQ(f.depth.type(), CV_16UC1);
    EXPECT_EQ(f.rgb.size(), cv::Size(640, 480));
    EXPECT_EQ(f.depth.size(), f.rgb.size());
    EXPECT_DOUBLE_EQ(f.depth_unit_m, 1e-3);
    EXPECT_TRUE(f.depth_aligned_to_color);
    EXPECT_DOUBLE_EQ(f.cam_color.fx, cam.fx);
    EXPECT_DOUBLE_EQ(f.cam_depth.cy, cam.cy);
    EXPECT_TRUE(f.T_color_depth.isApprox(Eigen::Isometry3d::Identity()));
    EXPECT_TRUE(f.has_source_T_body_cam);
    EXPECT_TRUE(f.source_T_body_cam.isApprox(ExtrinsicOptions().T_body_cam, 1e-7));
  }
  // The first frame (stamp 999.98) comes before the first IMU sample (1000.0).
  EXPECT_TRUE(rec.is_frame.front());

  // Without offset, an IMU sample with the same stamp as a frame comes first.
  const SimulatedSequence seq0(shortOptions(0.0));
  Recorder rec0;
  rec0.stop_flag = nullptr;
  seq0.pump(rec0);
  EXPECT_FALSE(rec0.is_frame[0]);
  EXPECT_TRUE(rec0.is_frame[1]);
  EXPECT_DOUBLE_EQ(rec0.stamps[0], rec0.stamps[1]);
}

TEST(SimulatedSequence, StopFlagEndsTheStreamEarly) {
  const SimulatedSequence seq(shortOptions());
  std::atomic<bool> stop{false};
  Recorder rec;
  rec.stop_flag = &stop;
  rec.stop_after = 100;
  seq.pump(rec, &stop);
  EXPECT_EQ(rec.stamps.size(), 100u);
  EXPECT_EQ(rec.ends, 1);
}

TEST(SimulatedSequence, FramesAreRenderedAtTheExposurePose) {
  const SimulatedSequence seq(shortOptions(0.03));
  const std::size_t i = 30;  // t = 6 s: moving
  cv::Mat rgb, depth_m;
  seq.renderIdeal(i, rgb, depth_m);
  const Renderer renderer(seq.scene(), seq.options().camera.camera, seq.options().render);
  cv::Mat rgb2, depth2;
  renderer.render(seq.groundTruth(1000.0 + 6.0).T_world_body * seq.options().extrinsic.T_body_cam,
                  rgb2, depth2);
  EXPECT_EQ(cv::norm(depth_m, depth2, cv::NORM_INF), 0.0);
  // Rendering at the (wrong) stamp time instead gives a different image: the offset is real.
  renderer.render(seq.cameraPose(1000.0 + 6.0 - 0.03), rgb2, depth2);
  EXPECT_GT(cv::norm(depth_m, depth2, cv::NORM_INF), 0.001);

  // Noisy depth is the ideal depth in millimetres plus D435-like noise, with ~1.5 % holes.
  const RgbdFrame f = seq.renderFrame(i);
  int valid = 0, holes = 0, compared = 0;
  double abs_err = 0.0;
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c) {
      const float z = depth_m.at<float>(r, c);
      if (z < 0.3f || z > 3.0f) continue;
      ++valid;
      const std::uint16_t d = f.depth.at<std::uint16_t>(r, c);
      if (d == 0) {
        ++holes;
        continue;
      }
      abs_err += std::abs(d * 1e-3 - z);
      ++compared;
    }
  ASSERT_GT(valid, 100000);
  EXPECT_NEAR(static_cast<double>(holes) / valid, 0.015, 0.01);
  EXPECT_LT(abs_err / compared, 0.015);  // mean |error| for sigma = 0.004 z^2 at <= 3 m
}

TEST(SimulatedSequence, SameSeedSameFramesDifferentSeedDifferentNoise) {
  const SimulatedSequence a(shortOptions()), b(shortOptions());
  SimOptions other = shortOptions();
  other.seed = 2;
  const SimulatedSequence c(other);
  const RgbdFrame fa = a.renderFrame(20), fb = b.renderFrame(20), fc = c.renderFrame(20);
  EXPECT_EQ(cv::norm(fa.rgb, fb.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
  cv::Mat diff;
  cv::compare(fa.depth, fc.depth, diff, cv::CMP_NE);
  EXPECT_GT(cv::countNonZero(diff), static_cast<int>(fa.depth.total() / 10));
  EXPECT_NE(a.imuSample(500).acc, c.imuSample(500).acc);
  // The motion is the same for every seed.
  EXPECT_TRUE(
      a.groundTruth(1005.0).T_world_body.isApprox(c.groundTruth(1005.0).T_world_body, 1e-15));
  // With and without prefetching the stream is identical.
  SimOptions no_prefetch = shortOptions();
  no_prefetch.prefetch_frames = false;
  const SimulatedSequence d(no_prefetch);
  Recorder ra, rd;
  a.pump(ra);
  d.pump(rd);
  ASSERT_EQ(ra.frames.size(), rd.frames.size());
  for (std::size_t i = 0; i < ra.frames.size(); i += 9)
    EXPECT_EQ(cv::norm(ra.frames[i].depth, rd.frames[i].depth, cv::NORM_INF), 0.0) << i;
}

TEST(SimulatedSequence, GroundTruthApi) {
  const SimulatedSequence seq(shortOptions(0.01));
  const double t = 1004.125;  // exactly 4.125 s after the start
  const GroundTruthState g = seq.groundTruth(t);
  const KinematicState s = seq.trajectory().state(4.125);
  EXPECT_TRUE(g.T_world_body.isApprox(s.T_world_body, 1e-15));
  EXPECT_EQ(g.v_world, s.v_world);
  EXPECT_EQ(g.bias.acc, seq.imu().biasAt(4.125).acc);
  const Eigen::Isometry3d& T_body_cam = seq.options().extrinsic.T_body_cam;
  EXPECT_TRUE(T_body_cam.isApprox(ExtrinsicOptions().T_body_cam, 1e-7));
  EXPECT_LT(
      (T_body_cam.linear().transpose() * T_body_cam.linear() - Eigen::Matrix3d::Identity()).norm(),
      1e-15);
  EXPECT_TRUE(seq.cameraPose(t).isApprox(s.T_world_body * T_body_cam, 1e-15));
  const Trajectory body = seq.bodyTrajectory(), cam = seq.cameraTrajectory();
  ASSERT_EQ(body.size(), seq.imuCount());
  ASSERT_EQ(cam.size(), seq.frameCount());
  EXPECT_DOUBLE_EQ(body[200].t, 1001.0);
  EXPECT_DOUBLE_EQ(cam[5].t, 1001.0 - 0.01);
  EXPECT_LT((cam[5].isometry().matrix() - seq.cameraPose(1001.0).matrix()).norm(), 1e-12)
      << cam[5].isometry().matrix() << "\n"
      << seq.cameraPose(1001.0).matrix();
  // The measured IMU minus its true bias averages to the ideal measurement.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t k = 1000; k < 1400; ++k)
    mean += (seq.imuSample(k).gyr - seq.imu().biasAtSample(k).gyr - seq.imu().ideal(k).gyr) / 400.0;
  EXPECT_LT(mean.norm(), 0.01);
}

TEST(SimOptions, DefaultsEqualTheSharedConfigAndAreAtLeastAsHardAsAD435i) {
  IniReader ini = IniReader::fromFile(test::sourceDir() + "/share/config.ini");
  const SimOptions o = SimOptions::load(ini);
  const SimOptions d;
  EXPECT_DOUBLE_EQ(o.fps, d.fps);
  EXPECT_EQ(o.seed, d.seed);
  EXPECT_DOUBLE_EQ(o.time_offset_s, d.time_offset_s);
  EXPECT_DOUBLE_EQ(o.start_time_s, d.start_time_s);
  EXPECT_DOUBLE_EQ(o.config_noise_inflation, d.config_noise_inflation);
  EXPECT_DOUBLE_EQ(o.imu.rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(o.imu.gravity_m_s2, 9.81);
  EXPECT_DOUBLE_EQ(o.imu.acc_noise_density, d.imu.acc_noise_density);
  EXPECT_DOUBLE_EQ(o.imu.gyr_noise_density, d.imu.gyr_noise_density);
  EXPECT_DOUBLE_EQ(o.imu.acc_random_walk, d.imu.acc_random_walk);
  EXPECT_DOUBLE_EQ(o.imu.gyr_random_walk, d.imu.gyr_random_walk);
  EXPECT_DOUBLE_EQ(o.imu.acc_bias_max, d.imu.acc_bias_max);
  EXPECT_DOUBLE_EQ(o.imu.gyr_bias_max, d.imu.gyr_bias_max);
  EXPECT_GE(o.imu.acc_noise_density, 0.02);
  EXPECT_GE(o.imu.gyr_noise_density, 0.002);
  EXPECT_GE(o.imu.acc_random_walk, 4e-4);
  EXPECT_GE(o.imu.gyr_random_walk, 2e-5);
  EXPECT_GE(o.imu.acc_bias_max, 0.1);
  EXPECT_GE(o.imu.gyr_bias_max, 0.005);
  const ProfileOptions& p = o.profile;
  EXPECT_EQ(p.speed, d.profile.speed);
  EXPECT_DOUBLE_EQ(p.duration_s, d.profile.duration_s);
  EXPECT_DOUBLE_EQ(p.speed_m_s, d.profile.speed_m_s);
  EXPECT_DOUBLE_EQ(p.rest_start_s, 2.0);
  EXPECT_DOUBLE_EQ(p.rest_end_s, d.profile.rest_end_s);
  EXPECT_DOUBLE_EQ(p.wheeled_vibration_acc_rms, d.profile.wheeled_vibration_acc_rms);
  EXPECT_DOUBLE_EQ(p.wheeled_vibration_gyr_rms, d.profile.wheeled_vibration_gyr_rms);
  EXPECT_DOUBLE_EQ(p.tracked_vibration_acc_rms, d.profile.tracked_vibration_acc_rms);
  EXPECT_DOUBLE_EQ(p.tracked_vibration_gyr_rms, d.profile.tracked_vibration_gyr_rms);
  EXPECT_DOUBLE_EQ(p.tracked_jitter_deg, d.profile.tracked_jitter_deg);
  EXPECT_DOUBLE_EQ(p.vibration_band_min_hz, 10.0);
  EXPECT_DOUBLE_EQ(p.vibration_band_max_hz, 30.0);
  EXPECT_DOUBLE_EQ(p.wheeled_camera_height_m, 0.3);
  EXPECT_DOUBLE_EQ(p.tracked_camera_height_m, d.profile.tracked_camera_height_m);
  EXPECT_DOUBLE_EQ(p.handheld_camera_height_m, d.profile.handheld_camera_height_m);
  // Every [sim] key of the shared config is read by the simulator (with the renderer's keys).
  ini.acceptConfigSectionsExcept({"sim", "extrinsic"});
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());

  IniReader bad = IniReader::fromText("[sim]\nfps = 0\n", "bad.ini");
  try {
    SimOptions::load(bad);
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ini"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fps"), std::string::npos) << e.what();
  }
}

/// Along a profile's whole path (a frame every 2 s): most of the image sees surfaces within
/// 0.5-4 m (D435 depth range), there are plenty of corners, and the camera never sits against
/// or inside an object.
void expectTexturedStructureNearTheCamera(const std::string& name, int variant) {
  SCOPED_TRACE(name + " variant " + std::to_string(variant));
  SimOptions o;
  o.profile.kind = parseProfileKind(name);
  o.profile.variant = variant;
  const SimulatedSequence seq(o);
  double sum_near = 0.0, min_near = 1.0;
  int frames = 0;
  std::size_t min_corners = 100000;
  cv::Mat rgb, depth, grey;
  for (std::size_t i = 0; i < seq.frameCount(); i += 60) {
    seq.renderIdeal(i, rgb, depth);
    int near = 0, too_close = 0;
    for (int r = 0; r < depth.rows; ++r)
      for (int c = 0; c < depth.cols; ++c) {
        const float z = depth.at<float>(r, c);
        near += (z >= 0.5f && z <= 4.0f);
        too_close += (z > 0.0f && z < 0.25f);
      }
    const double frac = static_cast<double>(near) / depth.total();
    sum_near += frac;
    min_near = std::min(min_near, frac);
    ++frames;
    EXPECT_LT(static_cast<double>(too_close) / depth.total(), 0.02) << name << " frame " << i;
    cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(grey, corners, 1000, 0.01, 15);
    min_corners = std::min(min_corners, corners.size());
  }
  std::printf(
      "%-15s variant %d, %d frames: depth in 0.5-4 m on %.0f %% of the image (min %.0f %%), >= %zu "
      "corners\n",
      name.c_str(), variant, frames, 100.0 * sum_near / frames, 100.0 * min_near, min_corners);
  EXPECT_GE(sum_near / frames, 0.6) << name;
  EXPECT_GE(min_near, 0.3) << name;
  EXPECT_GE(min_corners, 150u) << name;
}

TEST(ProfileScenes, TexturedStructureIsNearTheCameraAlongEveryPath) {
  for (const std::string& name : profileNames()) expectTexturedStructureNearTheCamera(name, 0);
}

// The other paths of the same world (rgbdi-sim --variant) see as much structure.
TEST(ProfileScenes, TexturedStructureIsNearTheCameraAlongEveryVariantPath) {
  for (const std::string& name : profileNames())
    for (int variant = 1; variant < kProfileVariants; ++variant)
      expectTexturedStructureNearTheCamera(name, variant);
}

TEST(SimulatedSequence, BlackoutFramesAreBlackWithoutDepthAndOnlyThose) {
  SimOptions o = shortOptions();
  o.blackout_start_s = 2.0;
  o.blackout_duration_s = 1.0;
  const SimulatedSequence seq(o);
  const SimulatedSequence plain(shortOptions());
  // At 5 Hz: frames 10..14 are exposed in [2 s, 3 s).
  for (std::size_t i : {9u, 10u, 12u, 14u, 15u}) {
    const RgbdFrame f = seq.renderFrame(i);
    const bool black = i >= 10 && i < 15;
    EXPECT_EQ(seq.inBlackout(i), black) << i;
    EXPECT_EQ(f.t, plain.frameStamp(i));
    EXPECT_EQ(f.rgb.type(), CV_8UC3);
    EXPECT_EQ(f.depth.type(), CV_16UC1);
    EXPECT_EQ(f.rgb.size(), plain.renderFrame(i).rgb.size());
    if (black) {
      EXPECT_EQ(cv::countNonZero(f.rgb.reshape(1)), 0) << i;
      EXPECT_EQ(cv::countNonZero(f.depth), 0) << i;
    } else {
      const RgbdFrame p = plain.renderFrame(i);
      EXPECT_EQ(cv::norm(f.rgb, p.rgb, cv::NORM_INF), 0.0) << i;
      EXPECT_EQ(cv::norm(f.depth, p.depth, cv::NORM_INF), 0.0) << i;
    }
  }
  // The IMU is unaffected.
  EXPECT_EQ(seq.imuSample(500).acc, plain.imuSample(500).acc);
}

TEST(SimulatedSequence, BareAndBlurredBlackoutFramesKeepTheirDepthAndLoseTheirCorners) {
  const SimulatedSequence plain(shortOptions());
  // Strongest corner response (Shi-Tomasi: the smaller eigenvalue of the gradients' matrix).
  auto strongest = [](const cv::Mat& rgb) {
    cv::Mat grey, response;
    cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
    cv::cornerMinEigenVal(grey, response, 5);
    double max_response = 0.0;
    cv::minMaxLoc(response, nullptr, &max_response);
    return max_response;
  };

  for (const std::string kind : {"bare", "blur"}) {
    SimOptions o = shortOptions();
    o.blackout_start_s = 2.0;
    o.blackout_duration_s = 1.0;
    o.blackout_kind = kind;
    const SimulatedSequence seq(o);
    const RgbdFrame f = seq.renderFrame(12), p = plain.renderFrame(12);
    EXPECT_TRUE(seq.inBlackout(12));
    // The same depth (same noise: one generator per frame), the colour impaired.
    EXPECT_EQ(cv::norm(f.depth, p.depth, cv::NORM_INF), 0.0) << kind;
    EXPECT_GT(cv::norm(f.rgb, p.rgb, cv::NORM_INF), 0.0) << kind;
    // Outside the blackout nothing changes.
    EXPECT_EQ(cv::norm(seq.renderFrame(9).rgb, plain.renderFrame(9).rgb, cv::NORM_INF), 0.0);
    if (kind == "bare") {
      // One colour plus the sensor's noise: every pixel within a few noise sigmas of the mean.
      cv::Scalar mean, stddev;
      cv::meanStdDev(f.rgb, mean, stddev);  // per channel
      for (int c = 0; c < 3; ++c) EXPECT_LT(stddev[c], 2.0 * o.color_noise.sigma + 1.0) << c;
    } else {
      // The smear: no corner as strong as a fifth of the sharp frame's strongest.
      EXPECT_LT(strongest(f.rgb), 0.2 * strongest(p.rgb)) << kind;
    }
  }
  SimOptions bad = shortOptions();
  bad.blackout_kind = "fog";
  EXPECT_THROW(SimulatedSequence{bad}, std::invalid_argument);
}

TEST(SimulatedSequence, SpinTurnsTheBodyAboutTheVerticalOnTopOfItsMotion) {
  SimOptions o = shortOptions();
  o.spin_start_s = 3.0;
  o.spin_duration_s = 1.0;
  o.spin_turns = 1.0;
  const SimulatedSequence spun(o), plain(shortOptions());
  const BodyTrajectory &a = spun.trajectory(), &b = plain.trajectory();
  auto expectSame = [](const KinematicState& x, const KinematicState& y, double t) {
    EXPECT_LT((x.T_world_body.matrix() - y.T_world_body.matrix()).norm(), 1e-9) << t;
    EXPECT_LT((x.omega_body - y.omega_body).norm(), 1e-9) << t;
    EXPECT_LT((x.v_world - y.v_world).norm(), 1e-12) << t;
  };
  // Before and after a whole turn: the profile's own motion.
  for (double t : {1.0, 2.99, 4.01, 6.5}) expectSame(a.state(t), b.state(t), t);
  // Mid-turn: half a turn about the world z axis at the smoothstep's peak rate
  // 2 pi * 35/16 / 1 s; position and velocity unchanged.
  const KinematicState mid = a.state(3.5), ref = b.state(3.5);
  const Eigen::Matrix3d half_turn =
      Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LT((mid.T_world_body.linear() - half_turn * ref.T_world_body.linear()).norm(), 1e-9);
  EXPECT_LT((mid.T_world_body.translation() - ref.T_world_body.translation()).norm(), 1e-12);
  // World-frame rate: the turn's plus the profile's own, turned with the body.
  const Eigen::Vector3d expected_world = Eigen::Vector3d(0, 0, 2.0 * M_PI * 35.0 / 16.0) +
                                         half_turn * ref.T_world_body.linear() * ref.omega_body;
  EXPECT_LT((mid.T_world_body.linear() * mid.omega_body - expected_world).norm(), 1e-9);
  // The angular rate is the derivative of the pose (4th-order differences), also while turning.
  const double h = 2e-4;
  for (double t : {3.1, 3.5, 3.77}) {
    const Eigen::Matrix3d R0 = a.pose(t).linear();
    auto rel = [&](double dt) { return logSO3(R0.transpose() * a.pose(t + dt).linear()); };
    const Eigen::Vector3d w_num = (rel(-2 * h) - 8 * rel(-h) + 8 * rel(h) - rel(2 * h)) / (12 * h);
    EXPECT_LT((w_num - a.state(t).omega_body).norm(), 1e-6) << t;
  }
  // The gyroscope measures it: at 200 Hz sample 700 is exposed at 3.5 s.
  const double dt_imu = spun.imuSample(1).t - spun.imuSample(0).t;
  const std::size_t k = static_cast<std::size_t>(std::lround(3.5 / dt_imu));
  EXPECT_NEAR(spun.imuSample(k).gyr.norm(), mid.omega_body.norm(), 0.1);
  EXPECT_GT(mid.omega_body.norm(), 13.0);

  SimOptions bad = shortOptions();
  bad.spin_duration_s = -1.0;
  EXPECT_THROW(SimulatedSequence{bad}, std::invalid_argument);
  bad.spin_duration_s = 1.0;
  bad.spin_turns = std::nan("");
  EXPECT_THROW(SimulatedSequence{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
