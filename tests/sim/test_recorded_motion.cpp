// The recorded trajectory (known answers: constant velocity / acceleration / body rate are
// interpolated exactly; rotation continuous and exact at the samples), the cut to the IMU's
// span, and the world around a recorded path (room encloses it, nothing within its corridor).
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/recorded_motion.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

Eigen::Matrix3d expSo3(const Eigen::Vector3d& w) {
  const double a = w.norm();
  return a > 0.0 ? Eigen::AngleAxisd(a, w / a).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

RecordedPose poseAt(double t, const Eigen::Vector3d& p, const Eigen::Matrix3d& R) {
  RecordedPose g;
  g.t = t;
  g.p_world = p;
  g.q_world_body = Eigen::Quaterniond(R);
  return g;
}

// Irregular stamps, as a motion-capture log has them.
const std::vector<double> kStamps = {0.0, 0.05, 0.09, 0.2, 0.26, 0.33, 0.4};

const Eigen::Vector3d kP0(0.3, -1.2, 0.8), kV(0.7, -0.4, 0.25), kA(0.9, 0.3, -1.1);
const Eigen::Vector3d kOmega(0.4, -1.1, 2.3);  // [rad/s] body rate, 0.15 rad per 0.06 s
const Eigen::Matrix3d kR0 = expSo3(Eigen::Vector3d(0.3, 2.0, -0.7));

TEST(RecordedTrajectory, ConstantVelocityAndBodyRateAreExact) {
  for (bool with_velocity : {true, false}) {
    std::vector<RecordedPose> samples;
    for (double t : kStamps) {
      RecordedPose g = poseAt(100.0 + t, kP0 + kV * t, kR0 * expSo3(kOmega * t));
      g.has_velocity = with_velocity;
      g.v_world = kV;
      samples.push_back(g);
    }
    const RecordedTrajectory traj(samples);
    EXPECT_EQ(traj.origin(), 100.0);
    EXPECT_NEAR(traj.duration(), 0.4, 1e-12);
    for (double t = 0.0; t <= 0.4; t += 0.0137) {
      const KinematicState s = traj.state(t);
      EXPECT_NEAR((s.T_world_body.translation() - (kP0 + kV * t)).norm(), 0.0, 1e-12) << t;
      EXPECT_NEAR((s.T_world_body.rotation() - kR0 * expSo3(kOmega * t)).norm(), 0.0, 1e-12) << t;
      EXPECT_NEAR((s.v_world - kV).norm(), 0.0, 1e-11) << t;
      EXPECT_NEAR(s.a_world.norm(), 0.0, 1e-9) << t;
      EXPECT_NEAR((s.omega_body - kOmega).norm(), 0.0, 1e-11) << t;
    }
  }
}

TEST(RecordedTrajectory, ConstantAccelerationWithRecordedVelocitiesIsExact) {
  std::vector<RecordedPose> samples;
  for (double t : kStamps) {
    RecordedPose g = poseAt(t, kP0 + kV * t + 0.5 * kA * t * t, kR0);
    g.has_velocity = true;
    g.v_world = kV + kA * t;
    samples.push_back(g);
  }
  const RecordedTrajectory traj(samples);
  for (double t = 0.0; t <= 0.4; t += 0.0137) {
    const KinematicState s = traj.state(t);
    EXPECT_NEAR((s.T_world_body.translation() - (kP0 + kV * t + 0.5 * kA * t * t)).norm(), 0.0,
                1e-12);
    EXPECT_NEAR((s.v_world - (kV + kA * t)).norm(), 0.0, 1e-11);
    EXPECT_NEAR((s.a_world - kA).norm(), 0.0, 1e-9);
    EXPECT_NEAR(s.omega_body.norm(), 0.0, 1e-12);
  }
}

TEST(RecordedTrajectory, RotationPassesThroughTheSamplesAndIsContinuous) {
  // Large steps about changing axes, every other quaternion stored with the opposite sign.
  std::vector<RecordedPose> samples;
  Eigen::Matrix3d R = kR0;
  for (std::size_t i = 0; i < kStamps.size(); ++i) {
    R = R * expSo3(Eigen::Vector3d(0.6 * std::sin(1.0 + i), 0.5 * std::cos(2.0 * i), 0.4));
    RecordedPose g = poseAt(kStamps[i], Eigen::Vector3d(i, -0.5 * i, 0.1 * i * i), R);
    if (i % 2) g.q_world_body.coeffs() = -g.q_world_body.coeffs();
    samples.push_back(g);
  }
  const RecordedTrajectory traj(samples);
  for (const RecordedPose& g : samples) {
    const Eigen::Isometry3d T = traj.pose(g.t);
    EXPECT_NEAR((T.rotation() - g.q_world_body.toRotationMatrix()).norm(), 0.0, 1e-12);
    EXPECT_NEAR((T.translation() - g.p_world).norm(), 0.0, 1e-12);
  }
  // No jump at a sample, and the angle to the sample shrinks with the distance in time.
  for (std::size_t i = 1; i + 1 < samples.size(); ++i) {
    const double t = samples[i].t;
    const Eigen::Quaterniond before(traj.pose(t - 1e-7).rotation()),
        after(traj.pose(t + 1e-7).rotation());
    EXPECT_LT(before.angularDistance(after), 1e-5) << i;
    // Velocity is continuous: both segments end at the sample's velocity (Hermite).
    const Eigen::Vector3d& v = traj.sampleVelocities()[i];
    EXPECT_NEAR((traj.state(t - 1e-12).v_world - v).norm(), 0.0, 1e-7) << i;
    EXPECT_NEAR((traj.state(t + 1e-12).v_world - v).norm(), 0.0, 1e-7) << i;
  }
  // Slerp takes the shorter arc: within a segment the angle to its start grows monotonically up
  // to the segment's angle (at most pi).
  for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
    const Eigen::Quaterniond q0 = samples[i].q_world_body, q1 = samples[i + 1].q_world_body;
    const double total = q0.angularDistance(q1);
    double last = 0.0;
    for (int k = 1; k <= 10; ++k) {
      const double t = samples[i].t + k * (samples[i + 1].t - samples[i].t) / 10.0;
      const double a = q0.angularDistance(Eigen::Quaterniond(traj.pose(t).rotation()));
      EXPECT_GT(a, last - 1e-12);
      EXPECT_NEAR(a, total * k / 10.0, 1e-9);
      last = a;
    }
  }
}

TEST(RecordedTrajectory, RejectsTooFewOrUnorderedSamples) {
  EXPECT_THROW(RecordedTrajectory({poseAt(0.0, kP0, kR0)}), std::invalid_argument);
  EXPECT_THROW(RecordedTrajectory({poseAt(1.0, kP0, kR0), poseAt(1.0, kP0, kR0)}),
               std::invalid_argument);
}

/// A recording whose IMU covers [1, 5] s at 200 Hz and whose ground truth covers [0.5, 6] s at
/// 10 Hz, moving along a figure of eight at 1-2 m height (a flying or hand-held sensor).
Recording syntheticRecording() {
  const double gt_step = 0.1;
  Recording r;
  r.directory = "synthetic";
  r.format = "euroc";
  for (int k = 0; k <= 800; ++k) {
    ImuSample s;
    s.t = 1.0 + k * 0.005;
    r.imu.push_back(s);
  }
  const int steps = static_cast<int>(std::lround(5.5 / gt_step));
  for (int i = 0; i <= steps; ++i) {
    const double t = 0.5 + i * gt_step;
    const Eigen::Vector3d p(2.0 * std::sin(0.8 * t), 1.5 * std::sin(1.6 * t),
                            1.5 + 0.5 * std::sin(0.5 * t));
    r.ground_truth.push_back(poseAt(t, p, expSo3(Eigen::Vector3d(0.1, -0.2, 0.8 * t))));
  }
  return r;
}

TEST(RecordedMotion, CutsToTheImuSpanAndTheDuration) {
  const Recording r = syntheticRecording();
  const RecordedMotion m = makeRecordedMotion(r, RecordedWorldOptions{});
  EXPECT_NEAR(r.ground_truth[m.first_pose].t, 1.0, 1e-9);  // first sample with IMU before it
  EXPECT_NEAR(r.ground_truth[m.last_pose].t, 5.0, 1e-9);   // last sample with IMU after it
  EXPECT_EQ(m.imu_count, 801u);
  EXPECT_EQ(m.trajectory->origin(), r.ground_truth[m.first_pose].t);
  EXPECT_NEAR(m.trajectory->duration(), 4.0, 1e-9);
  EXPECT_EQ(m.profile.kind, ProfileKind::Recorded);
  EXPECT_EQ(toString(m.profile.kind), "recorded");
  // Not a synthesised profile: neither parsed as one nor made by makeMotionProfile.
  EXPECT_THROW(parseProfileKind("recorded"), std::invalid_argument);
  ProfileOptions po;
  po.kind = ProfileKind::Recorded;
  EXPECT_THROW(makeMotionProfile(po, Eigen::Isometry3d::Identity()), std::invalid_argument);

  const RecordedMotion cut = makeRecordedMotion(r, RecordedWorldOptions{}, 2.0);
  EXPECT_NEAR(r.ground_truth[cut.last_pose].t, 3.0, 1e-9);
  EXPECT_EQ(cut.imu_count, 401u);  // IMU samples up to the last pose (1.0 .. 3.0 s)
}

TEST(RecordedMotion, ErrorsOnGapsAndOnGroundTruthOutsideTheImu) {
  Recording r = syntheticRecording();
  r.ground_truth.erase(r.ground_truth.begin() + 20, r.ground_truth.begin() + 25);
  try {
    makeRecordedMotion(r, RecordedWorldOptions{});
    FAIL() << "a 0.6 s gap must be refused";
  } catch (const RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find("recording synthetic: ground truth has a gap of 0.6"),
              std::string::npos)
        << e.what();
  }
  Recording late = syntheticRecording();
  for (ImuSample& s : late.imu) s.t += 10.0;
  EXPECT_THROW(makeRecordedMotion(late, RecordedWorldOptions{}), RecordingError);
}

/// Rays from p: none hits anything within `clear` horizontally, and straight down the first
/// hit is the floor.
void expectFreeAround(const Scene& scene, const Eigen::Vector3d& p, double clear, double floor_z,
                      const std::string& what) {
  Hit hit;
  for (int k = 0; k < 36; ++k) {
    const double a = k * M_PI / 18.0;
    if (scene.raycast(p, Eigen::Vector3d(std::cos(a), std::sin(a), 0.0), clear, hit))
      ADD_FAILURE() << what << ": something at " << hit.t << " m in direction " << a;
  }
  ASSERT_TRUE(scene.raycast(p, -Eigen::Vector3d::UnitZ(), 100.0, hit)) << what;
  EXPECT_NEAR(hit.point.z(), floor_z, 1e-9) << what << ": not the floor below";
}

void expectWorldAroundPath(const RecordedMotion& m, const RecordedWorldOptions& o,
                           const Eigen::Isometry3d& T_body_cam) {
  const Scene scene = buildProfileScene(m.profile, 1);
  const ProfileLayout& l = m.profile.layout;
  EXPECT_GT(scene.primitiveCount(), 6u + 4u) << "room and furniture";
  const double floor_z = l.room_min.z();
  Eigen::AlignedBox3d path;
  for (double t = 0.0; t <= m.trajectory->duration(); t += 0.05) {
    const Eigen::Isometry3d T = m.trajectory->pose(t);
    path.extend(T.translation());
    // The body keeps the corridor up to the spacing of the path points; the camera, a few
    // centimetres off the body, nearly so.
    expectFreeAround(scene, T.translation(), o.path_clearance_m - 0.07, floor_z, "body");
    expectFreeAround(scene, (T * T_body_cam).translation(),
                     o.path_clearance_m - 0.07 - T_body_cam.translation().norm(), floor_z,
                     "camera");
  }
  const Eigen::Vector3d margin(o.room_margin_m, o.room_margin_m, 0.0);
  EXPECT_NEAR((l.room_min - (path.min() - margin)).head<2>().norm(), 0.0, 0.05);
  EXPECT_NEAR((l.room_max - (path.max() + margin)).head<2>().norm(), 0.0, 0.05);
  EXPECT_NEAR(l.room_min.z(), path.min().z() - o.floor_below_m, 0.01);
  EXPECT_NEAR(l.room_max.z(), path.max().z() + o.ceiling_above_m, 0.01);
  EXPECT_TRUE(scene.bounds().contains(path));
}

TEST(RecordedMotion, WorldEnclosesThePathAndKeepsItsCorridorFree) {
  const RecordedWorldOptions o;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.translation() = Eigen::Vector3d(0.02, -0.06, 0.01);
  expectWorldAroundPath(makeRecordedMotion(syntheticRecording(), o), o, T_body_cam);
}

TEST(RecordedMotion, WorldAroundTheEurocFlight) {
  const std::string dir = test::fixturePath("euroc_v102");
  RGBDI_REQUIRE_FIXTURE(dir + "/groundtruth.csv");
  const Recording r = readEurocRecording(dir);
  const RecordedWorldOptions o;
  const RecordedMotion m = makeRecordedMotion(r, o);
  // The first ground-truth sample is 1.01 s after the first IMU sample; the IMU ends first.
  EXPECT_EQ(m.first_pose, 0u);
  EXPECT_NEAR(r.ground_truth[m.last_pose].t - r.imu.front().t, 39.985, 0.03);
  EXPECT_EQ(m.last_pose, 1559u);
  EXPECT_EQ(m.imu_count, r.imu.size() - 1);  // the file's last IMU sample follows the last pose
  expectWorldAroundPath(m, o, r.T_body_cam);
}

TEST(RecordedWorldOptions, DefaultsEqualTheSharedConfigAndRangesAreChecked) {
  IniReader ini = IniReader::fromFile(test::sourceDir() + "/share/config.ini");
  const RecordedWorldOptions o = RecordedWorldOptions::load(ini), d;
  EXPECT_EQ(o.room_margin_m, d.room_margin_m);
  EXPECT_EQ(o.floor_below_m, d.floor_below_m);
  EXPECT_EQ(o.ceiling_above_m, d.ceiling_above_m);
  EXPECT_EQ(o.path_clearance_m, d.path_clearance_m);
  EXPECT_EQ(o.max_gap_s, d.max_gap_s);
  IniReader bad = IniReader::fromText("[sim]\nrecorded_path_clearance_m = 0\n", "test.ini");
  try {
    RecordedWorldOptions::load(bad);
    FAIL() << "a zero clearance must be refused";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("recorded_path_clearance_m"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::sim
