// D435-like depth artefacts (flying pixels, holes on dark surfaces and at grazing incidence) and
// jittered image stamps.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/sim/depth_artefacts.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"

namespace rgbdi::sim {
namespace {

PinholeCamera camera() {
  PinholeCamera c;
  c.width = 320;
  c.height = 240;
  c.fx = c.fy = 300.0;
  c.cx = 159.5;
  c.cy = 119.5;
  return c;
}

cv::Mat flat(double z) { return cv::Mat(240, 320, CV_32FC1, cv::Scalar(z)); }
cv::Mat grey(int level) { return cv::Mat(240, 320, CV_8UC3, cv::Scalar::all(level)); }

/// Depth of the plane n.X = d (unit normal n) seen by camera(), 0 where it is behind the camera
/// or farther than 10 m.
cv::Mat plane(const Eigen::Vector3d& n, double d) {
  const PinholeCamera c = camera();
  cv::Mat z(c.height, c.width, CV_32FC1);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const Eigen::Vector3d ray((x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0);
      const double depth = d / n.dot(ray);
      z.at<float>(y, x) = depth > 0.0 && depth < 10.0 ? static_cast<float>(depth) : 0.0f;
    }
  return z;
}

double holeFraction(const cv::Mat& depth) {
  return 1.0 - static_cast<double>(cv::countNonZero(depth)) / depth.total();
}

TEST(DepthArtefacts, OffLeavesTheDepthUntouched) {
  cv::Mat z = plane(Eigen::Vector3d(0.3, 0.1, 1.0).normalized(), 2.0), before = z.clone();
  std::mt19937_64 rng(1);
  applyDepthArtefacts(z, grey(0), camera(), DepthArtefactOptions{}, rng);
  EXPECT_EQ(cv::norm(z, before, cv::NORM_INF), 0.0);
}

TEST(DepthArtefacts, FlyingPixelsMixForeAndBackgroundOnDepthEdgesOnly) {
  cv::Mat step = flat(1.0);
  step.colRange(160, 320).setTo(3.0);
  DepthArtefactOptions o;
  o.flying_pixel_prob = 1.0;
  cv::Mat z = step.clone();
  std::mt19937_64 rng(2);
  applyDepthArtefacts(z, grey(128), camera(), o, rng);
  for (int y = 0; y < z.rows; ++y)
    for (int x = 0; x < z.cols; ++x) {
      const float v = z.at<float>(y, x);
      if (x == 159 || x == 160) {
        EXPECT_GT(v, 1.0f);
        EXPECT_LT(v, 3.0f);
      } else {
        ASSERT_EQ(v, step.at<float>(y, x)) << x << " " << y;
      }
    }
  // Half of the 480 edge pixels at probability 0.5 (binomial std 11).
  o.flying_pixel_prob = 0.5;
  z = step.clone();
  applyDepthArtefacts(z, grey(128), camera(), o, rng);
  cv::Mat changed;
  cv::compare(z, step, changed, cv::CMP_NE);
  EXPECT_NEAR(cv::countNonZero(changed), 240, 40);
  // A step smaller than the edge jump is no edge.
  step.colRange(160, 320).setTo(1.05);
  z = step.clone();
  o.flying_pixel_prob = 1.0;
  applyDepthArtefacts(z, grey(128), camera(), o, rng);
  EXPECT_EQ(cv::norm(z, step, cv::NORM_INF), 0.0);
}

TEST(DepthArtefacts, DarkSurfacesLoseDepthByTheirLuminance) {
  DepthArtefactOptions o;
  o.dark_hole_prob = 1.0;
  o.dark_level = 40.0;
  cv::Mat rgb = grey(0);
  rgb.colRange(160, 320).setTo(cv::Scalar::all(40));
  cv::Mat z = flat(2.0);
  std::mt19937_64 rng(3);
  applyDepthArtefacts(z, rgb, camera(), o, rng);
  EXPECT_EQ(cv::countNonZero(z.colRange(0, 160)), 0);            // black: always a hole
  EXPECT_EQ(cv::countNonZero(z.colRange(160, 320)), 160 * 240);  // at dark_level: never
  // Luminance 20 of 40: probability 0.5 (76800 pixels: std 0.002).
  z = flat(2.0);
  applyDepthArtefacts(z, grey(20), camera(), o, rng);
  EXPECT_NEAR(holeFraction(z), 0.5, 0.01);
  o.dark_hole_prob = 0.4;
  z = flat(2.0);
  applyDepthArtefacts(z, grey(20), camera(), o, rng);
  EXPECT_NEAR(holeFraction(z), 0.2, 0.01);
}

TEST(DepthArtefacts, GrazingIncidenceLosesDepthAsTheAngleApproachesNinetyDegrees) {
  const PinholeCamera c = camera();
  // The incidence angle estimated from the depth image equals the true one.
  // A wall seen at 80 deg on the optical axis (it leaves the view at x ~ 107 on the left).
  const Eigen::Vector3d n = Eigen::Vector3d(std::sin(1.4), 0.0, std::cos(1.4));
  const cv::Mat tilted = plane(n, 1.0);
  const double jump = 10.0;  // no depth edges on this plane
  int checked = 0;
  for (int x : {20, 120, 160, 250, 318})
    for (int y : {10, 120, 230}) {
      const Eigen::Vector3d ray((x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0);
      const double truth = std::acos(std::abs(n.dot(ray.normalized())));
      if (incidenceAngle(tilted, c, x, y, jump) < 0.0) continue;
      EXPECT_NEAR(incidenceAngle(tilted, c, x, y, jump), truth, 2e-3) << x << " " << y;
      ++checked;
    }
  EXPECT_GE(checked, 9);
  EXPECT_LT(incidenceAngle(tilted, c, 0, 5, jump), 0.0);   // no neighbour on the border
  EXPECT_LT(incidenceAngle(tilted, c, 20, 5, jump), 0.0);  // no depth

  DepthArtefactOptions o;
  o.grazing_hole_prob = 1.0;
  o.grazing_angle_deg = 70.0;
  o.edge_jump_m = jump;
  cv::Mat z = plane(Eigen::Vector3d::UnitZ(), 2.0);  // fronto-parallel: at most 33 deg
  std::mt19937_64 rng(4);
  applyDepthArtefacts(z, grey(128), c, o, rng);
  EXPECT_EQ(holeFraction(z), 0.0);
  // The tilted plane: hole fraction = mean of the per-pixel probability.
  z = tilted.clone();
  applyDepthArtefacts(z, grey(128), c, o, rng);
  double expected = 0.0;
  int valid = 0;
  int holes = 0;
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      if (incidenceAngle(tilted, c, x, y, jump) < 0.0) {
        // No normal (border, no depth around): never a grazing hole.
        ASSERT_EQ(z.at<float>(y, x), tilted.at<float>(y, x));
        continue;
      }
      const Eigen::Vector3d ray((x - c.cx) / c.fx, (y - c.cy) / c.fy, 1.0);
      const double angle = std::acos(std::abs(n.dot(ray.normalized())));
      expected += std::max(0.0, (angle - 70.0 * M_PI / 180.0) / (20.0 * M_PI / 180.0));
      ++valid;
      holes += z.at<float>(y, x) == 0.0f;
    }
  expected /= valid;
  EXPECT_GT(expected, 0.1);  // 0.15: a real share of the plane
  EXPECT_NEAR(static_cast<double>(holes) / valid, expected, 0.01);
}

TEST(DepthArtefacts, OptionsLoadAndSequencesShowThem) {
  IniReader ini = IniReader::fromText(
      "[sim]\ndepth_flying_pixel_prob = 0.5\ndepth_edge_jump_m = 0.2\ndepth_dark_hole_prob = 0.3\n"
      "depth_dark_level = 30\ndepth_grazing_hole_prob = 0.6\ndepth_grazing_angle_deg = 75\n"
      "frame_stamp_jitter_s = 0.002\nduration_s = 9\nfps = 5\n",
      "depth.ini");
  SimOptions o = SimOptions::load(ini);
  EXPECT_EQ(o.depth_artefacts.flying_pixel_prob, 0.5);
  EXPECT_EQ(o.depth_artefacts.edge_jump_m, 0.2);
  EXPECT_EQ(o.depth_artefacts.dark_hole_prob, 0.3);
  EXPECT_EQ(o.depth_artefacts.dark_level, 30.0);
  EXPECT_EQ(o.depth_artefacts.grazing_hole_prob, 0.6);
  EXPECT_EQ(o.depth_artefacts.grazing_angle_deg, 75.0);
  EXPECT_EQ(o.frame_stamp_jitter_s, 0.002);
  for (const std::string bad : {"depth_flying_pixel_prob = 1.5", "depth_grazing_angle_deg = 90",
                                "depth_dark_level = 0", "frame_stamp_jitter_s = 0.02"}) {
    IniReader b = IniReader::fromText("[sim]\n" + bad + "\n", "bad.ini");
    try {
      SimOptions::load(b);
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.substr(0, bad.find(' '))), std::string::npos)
          << e.what();
    }
  }

  // A rendered frame with the artefacts has more holes; its colour is unchanged.
  o.profile.kind = ProfileKind::WheeledCircle;
  o.prefetch_frames = false;
  SimOptions plain_options = o;
  plain_options.depth_artefacts = DepthArtefactOptions{};
  const SimulatedSequence with(o), plain(plain_options);
  const RgbdFrame a = with.renderFrame(20), b = plain.renderFrame(20);
  EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0);
  EXPECT_GT(holeFraction(a.depth), holeFraction(b.depth) + 0.002)
      << holeFraction(a.depth) << " " << holeFraction(b.depth);
}

TEST(SensorRealism, EverySetKeyIsWrittenToSimulationIniAndReadsBackEqual) {
  IniReader ini = IniReader::fromText(
      "[sim]\nduration_s = 9\nimu_acc_scale_max = 0.01\nimu_gyr_scale_max = 0.02\n"
      "imu_acc_misalignment_max_rad = 0.003\nimu_gyr_misalignment_max_rad = 0.004\n"
      "imu_gyr_g_sensitivity_max = 1.8e-4\nimu_acc_bias_instability = 0.002\n"
      "imu_gyr_bias_instability = 1e-4\nimu_bias_instability_tau_s = 50\nimu_acc_lsb = 0.0191\n"
      "imu_gyr_lsb = 5.3e-4\nimu_accel_rate_hz = 250\nimu_gyro_rate_hz = 400\n"
      "depth_flying_pixel_prob = 0.5\ndepth_edge_jump_m = 0.2\ndepth_dark_hole_prob = 0.3\n"
      "depth_dark_level = 30\ndepth_grazing_hole_prob = 0.6\ndepth_grazing_angle_deg = 75\n"
      "frame_stamp_jitter_s = 0.002\n",
      "real.ini");
  SimOptions o = SimOptions::load(ini);
  o.profile.kind = ProfileKind::WheeledCircle;
  const SimulatedSequence seq(o);
  IniReader again = IniReader::fromText(simulationSettingsText(seq), "simulation.ini");
  const SimOptions r = SimOptions::load(again);
  const ImuErrorOptions &e = r.imu.errors, &x = o.imu.errors;
  EXPECT_EQ(e.acc_scale_max, x.acc_scale_max);
  EXPECT_EQ(e.gyr_scale_max, x.gyr_scale_max);
  EXPECT_EQ(e.acc_misalignment_max_rad, x.acc_misalignment_max_rad);
  EXPECT_EQ(e.gyr_misalignment_max_rad, x.gyr_misalignment_max_rad);
  EXPECT_EQ(e.gyr_g_sensitivity_max, x.gyr_g_sensitivity_max);
  EXPECT_EQ(e.acc_bias_instability, x.acc_bias_instability);
  EXPECT_EQ(e.gyr_bias_instability, x.gyr_bias_instability);
  EXPECT_EQ(e.bias_instability_tau_s, x.bias_instability_tau_s);
  EXPECT_EQ(e.acc_lsb, x.acc_lsb);
  EXPECT_EQ(e.gyr_lsb, x.gyr_lsb);
  EXPECT_EQ(r.imu.accel_rate_hz, 250.0);
  EXPECT_EQ(r.imu.gyro_rate_hz, 400.0);
  EXPECT_EQ(r.imu.rate_hz, 400.0);  // the merged samples' rate
  const DepthArtefactOptions &a = r.depth_artefacts, &y = o.depth_artefacts;
  EXPECT_EQ(a.flying_pixel_prob, y.flying_pixel_prob);
  EXPECT_EQ(a.edge_jump_m, y.edge_jump_m);
  EXPECT_EQ(a.dark_hole_prob, y.dark_hole_prob);
  EXPECT_EQ(a.dark_level, y.dark_level);
  EXPECT_EQ(a.grazing_hole_prob, y.grazing_hole_prob);
  EXPECT_EQ(a.grazing_angle_deg, y.grazing_angle_deg);
  EXPECT_EQ(r.frame_stamp_jitter_s, 0.002);
}

TEST(FrameStampJitter, StampsJitterWithinTheBoundAndTheGroundTruthStaysAtTheExposure) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 20.0;
  o.fps = 30.0;
  o.frame_stamp_jitter_s = 0.003;
  o.time_offset_s = 0.01;
  const SimulatedSequence seq(o), again(o);
  double sum2 = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < seq.frameCount(); ++i) {
    const double e = seq.frameStamp(i) - seq.frameTrueStamp(i);
    EXPECT_EQ(seq.frameStamp(i), again.frameStamp(i));
    EXPECT_NEAR(seq.frameTrueStamp(i), 1000.0 + i / 30.0 - 0.01, 1e-9);
    sum2 += e * e;
    largest = std::max(largest, std::abs(e));
  }
  EXPECT_LE(largest, 0.003);
  EXPECT_GT(largest, 0.0029);
  // Uniform in +-3 ms: RMS 3 / sqrt(3) = 1.73 ms.
  EXPECT_NEAR(std::sqrt(sum2 / seq.frameCount()), 0.003 / std::sqrt(3.0), 1e-4);
  const Trajectory cam = seq.cameraTrajectory();
  for (std::size_t i = 0; i < cam.size(); i += 50) {
    EXPECT_NEAR(cam[i].t, seq.frameTrueStamp(i), 1e-12);
    EXPECT_TRUE(cam[i].isometry().isApprox(seq.cameraPose(seq.frameExposureTime(i)), 1e-12));
  }
  o.frame_stamp_jitter_s = 0.01;  // more than a quarter of the frame period
  EXPECT_THROW(SimulatedSequence{o}, std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
