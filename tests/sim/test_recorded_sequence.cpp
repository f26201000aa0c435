// A hybrid sequence: the recording's IMU samples delivered and written unchanged (values exact,
// stamps in the recording's clock), frames rendered along its ground truth, the ground truth
// written at its own stamps, config.ini holding the recording's sensor noise.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/sim/sequence_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

// Stamps of the EuRoC era, where a double resolves 0.24 us.
constexpr double kClock = 1403715523.0;

/// IMU over [1, 5] s after kClock at 200 Hz with distinct values; ground truth over
/// [0.5, 6] s at 40 Hz with velocities and biases, moving along a figure of eight.
std::shared_ptr<const Recording> recording() {
  auto r = std::make_shared<Recording>();
  r->directory = "synthetic";
  r->format = "euroc";
  r->sensor.name = "test IMU";
  r->sensor.rate_hz = 200.0;
  r->sensor.gyr_noise_density = 1.6968e-4;
  r->sensor.gyr_random_walk = 1.9393e-5;
  r->sensor.acc_noise_density = 2.0e-3;
  r->sensor.acc_random_walk = 3.0e-3;
  for (int k = 0; k <= 800; ++k) {
    ImuSample s;
    s.t = kClock + 1.0 + k * 0.005;
    s.gyr = Eigen::Vector3d(0.001 * k, std::sin(0.1 * k), -0.3);
    s.acc = Eigen::Vector3d(0.1, std::cos(0.07 * k), 9.81 + 1e-4 * k);
    r->imu.push_back(s);
  }
  for (int i = 0; i <= 220; ++i) {
    const double t = 0.5 + i * 0.025;
    RecordedPose g;
    g.t = kClock + t;
    g.p_world = Eigen::Vector3d(2.0 * std::sin(0.8 * t), 1.5 * std::sin(1.6 * t), 1.5);
    g.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(0.8 * t, Eigen::Vector3d::UnitZ()));
    g.has_velocity = true;
    g.v_world = Eigen::Vector3d(1.6 * std::cos(0.8 * t), 2.4 * std::cos(1.6 * t), 0.0);
    g.has_bias = true;
    g.bias.gyr = Eigen::Vector3d(0.01, 0.02, 0.03 + 0.001 * t);
    g.bias.acc = Eigen::Vector3d(-0.1, 0.2, 0.3);
    r->ground_truth.push_back(g);
  }
  return r;
}

/// Keeps what a sequence delivers.
struct KeepingSink : MeasurementSink {
  std::vector<ImuSample> imu;
  std::vector<double> frame_stamps;
  double last = -1.0;
  bool ordered = true;
  void feedImu(const ImuSample& s) override {
    ordered = ordered && s.t >= last;
    last = s.t;
    imu.push_back(s);
  }
  void feedRgbd(const RgbdFrame& f) override {
    ordered = ordered && f.t >= last;
    last = f.t;
    frame_stamps.push_back(f.t);
  }
  void endOfStream() override {}
};

SimOptions options(double duration_s = 0.0) {
  SimOptions o;
  o.recording = recording();
  o.profile.kind = ProfileKind::Recorded;
  o.profile.duration_s = duration_s;
  o.fps = 5.0;
  return o;
}

TEST(RecordedSequence, ReplaysTheRecordedImuAndRendersAlongTheGroundTruth) {
  const SimOptions o = options();
  const SimulatedSequence seq(o);
  ASSERT_TRUE(seq.isRecorded());
  EXPECT_THROW(seq.imu(), std::logic_error);
  EXPECT_EQ(seq.startTime(), kClock + 1.0);  // the first ground-truth sample inside the IMU
  EXPECT_NEAR(seq.duration(), 4.0, 1e-6);
  EXPECT_EQ(seq.frameCount(), 21u);  // 4 s at 5 Hz, both ends
  ASSERT_EQ(seq.imuCount(), 801u);
  for (std::size_t k = 0; k < seq.imuCount(); ++k) {
    const ImuSample s = seq.imuSample(k);
    EXPECT_EQ(s.t, o.recording->imu[k].t);
    EXPECT_EQ(s.gyr, o.recording->imu[k].gyr);
    EXPECT_EQ(s.acc, o.recording->imu[k].acc);
  }
  // Ground truth at the recording's samples is the recording; biases interpolate.
  for (const RecordedPose& g : o.recording->ground_truth) {
    if (g.t < seq.startTime() || g.t > seq.startTime() + seq.duration()) continue;
    const GroundTruthState s = seq.groundTruth(g.t);
    EXPECT_NEAR((s.T_world_body.translation() - g.p_world).norm(), 0.0, 1e-6);
    EXPECT_NEAR(Eigen::Quaterniond(s.T_world_body.rotation()).angularDistance(g.q_world_body), 0.0,
                1e-6);
    EXPECT_NEAR((s.v_world - g.v_world).norm(), 0.0, 1e-6);
    EXPECT_NEAR((s.bias.gyr - g.bias.gyr).norm(), 0.0, 1e-12);
  }
  const ImuBias b0 = seq.initialBias();
  EXPECT_NEAR(b0.gyr.z(), 0.03 + 0.001, 1e-9);  // the ground truth's bias at the first IMU stamp
  // Frames at fps from the start, rendered from T_world_body * T_body_cam.
  EXPECT_EQ(seq.frameExposureTime(3), seq.startTime() + 0.6);
  // (Stamps near 1.4e9 s resolve 0.24 us: the pose is that of 0.6 s within 0.5 um at 2 m/s.)
  const Eigen::Isometry3d expected =
      seq.trajectory().pose(0.6) * seq.options().extrinsic.T_body_cam;
  const Eigen::Isometry3d camera = seq.cameraPose(seq.frameExposureTime(3));
  EXPECT_LT((camera.translation() - expected.translation()).norm(), 1e-6);
  EXPECT_LT((camera.rotation() - expected.rotation()).norm(), 1e-6);
  // The stream: every recorded IMU sample and every frame, in stamp order.
  KeepingSink sink;
  seq.pump(sink);
  EXPECT_TRUE(sink.ordered);
  ASSERT_EQ(sink.imu.size(), 801u);
  ASSERT_EQ(sink.frame_stamps.size(), 21u);
  EXPECT_EQ(sink.imu.front().t, o.recording->imu.front().t);
}

TEST(RecordedSequence, CutsToADurationAndRefusesASpin) {
  const SimulatedSequence cut(options(2.0));
  EXPECT_NEAR(cut.duration(), 2.0, 1e-6);
  EXPECT_EQ(cut.frameCount(), 11u);
  EXPECT_EQ(cut.imuCount(), 401u);  // up to the last replayed ground-truth sample
  SimOptions spin = options();
  spin.spin_duration_s = 1.0;
  EXPECT_THROW(SimulatedSequence{spin}, std::invalid_argument);
}

TEST(RecordedSequence, WrittenRawlogHoldsTheRecordedImuExactly) {
  const std::string dir = test::makeTempDir("recorded_seq");
  const SimulatedSequence seq(options(1.0));
  SequenceWriterOptions wo;
  wo.write_bag = true;
  const SequenceWriteSummary s = writeSequence(seq, dir, wo);
  ASSERT_TRUE(s.completed);
  const Recording& rec = *seq.options().recording;
  io::RawlogSource src(s.rawlog_path);
  io::Measurement m;
  std::size_t imu = 0, frames = 0;
  while (src.next(m)) {
    if (io::isImu(m)) {
      const ImuSample& a = std::get<ImuSample>(m);
      ASSERT_LT(imu, rec.imu.size());
      const ImuSample& b = rec.imu[imu++];
      // MRPT stamps are 100 ns ticks and a double at 1.4e9 s resolves 0.24 us.
      EXPECT_NEAR(a.t, b.t, 3e-7);
      EXPECT_EQ(a.acc, b.acc);
      EXPECT_EQ(a.gyr, b.gyr);
    } else {
      ++frames;
    }
  }
  EXPECT_EQ(imu, seq.imuCount());
  EXPECT_EQ(frames, seq.frameCount());

  // groundtruth.tum: the recording's samples at their stamps within the replayed IMU span.
  const Trajectory gt = eval::readTum(s.groundtruth_path);
  std::size_t n = 0;
  for (const RecordedPose& g : rec.ground_truth) {
    if (g.t < rec.imu.front().t || g.t > seq.imuSample(seq.imuCount() - 1).t) continue;
    ASSERT_LT(n, gt.size());
    EXPECT_NEAR(gt[n].t, g.t, 1e-6);
    EXPECT_NEAR(gt[n].p.x(), g.p_world.x(), 1e-9);
    EXPECT_NEAR(std::abs(gt[n].q.w()), std::abs(g.q_world_body.w()), 1e-9);
    ++n;
  }
  EXPECT_EQ(n, gt.size());
  EXPECT_EQ(n, 41u);  // 1.0 .. 2.0 s at 40 Hz

  // config.ini: the recording's sensor, inflated as for the simulated profiles.
  IniReader ini = IniReader::fromFile(s.config_path);
  const double k = seq.options().config_noise_inflation;
  EXPECT_NEAR(ini.getDouble("imu", "gyr_noise_density", 0, 0, 1), k * 1.6968e-4, 1e-12);
  EXPECT_NEAR(ini.getDouble("imu", "acc_random_walk", 0, 0, 1), k * 3.0e-3, 1e-12);
  EXPECT_NEAR(ini.getDouble("imu", "rate_hz", 0, 0, 1000), 200.0, 1e-12);
  // The bag: every replayed IMU sample and the recording's ground truth at its own stamps.
  rosbag::Bag bag(s.bag_path, rosbag::bagmode::Read);
  std::map<std::string, int> count;
  std::vector<double> pose_stamps;
  for (const rosbag::MessageInstance& msg : rosbag::View(bag)) {
    ++count[msg.getTopic()];
    if (auto pose = msg.instantiate<geometry_msgs::PoseStamped>())
      pose_stamps.push_back(pose->header.stamp.toSec());
  }
  EXPECT_EQ(count["/camera/imu"], 201);
  EXPECT_EQ(count["/camera/color/image_raw"], 6);
  ASSERT_EQ(pose_stamps.size(), 41u);
  EXPECT_NEAR(pose_stamps.front(), gt.front().t, 1e-6);
  EXPECT_NEAR(pose_stamps.back(), gt.back().t, 1e-6);
  std::ifstream settings(s.simulation_path);
  std::stringstream text;
  text << settings.rdbuf();
  EXPECT_NE(text.str().find("--profile recorded --recording synthetic --recording-format euroc"),
            std::string::npos);
}

}  // namespace
}  // namespace rgbdi::sim
