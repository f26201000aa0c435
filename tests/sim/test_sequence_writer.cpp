// writeSequence: every output file, read back with the project's own readers (rawlog source,
// config loaders, rosbag) and compared with the in-process sequence; determinism of the bytes.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/sim/sequence_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

namespace fs = std::filesystem;

SimOptions shortOptions(std::uint64_t seed = 1) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.fps = 4.0;
  o.seed = seed;
  o.time_offset_s = 0.015;
  return o;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream os;
  os << f.rdbuf();
  return os.str();
}

/// Every file below dir (relative path -> bytes).
std::map<std::string, std::string> tree(const std::string& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = slurp(e.path().string());
  return files;
}

/// Lines of a TUM file that are not comments.
std::vector<std::vector<double>> readTumLines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(f, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream is(line);
    std::vector<double> v(8);
    for (double& x : v) is >> x;
    rows.push_back(v);
  }
  return rows;
}

TEST(SequenceWriter, WritesReadableRawlogGroundTruthConfigAndBag) {
  const std::string dir = test::makeTempDir("simseq");
  const SimulatedSequence seq(shortOptions());
  SequenceWriterOptions wo;
  wo.write_bag = true;
  wo.bag_compression = bag::Compression::Lz4;
  std::ostringstream progress;
  wo.progress = &progress;
  // Not a terminal (a log): one line per tenth of the frames however short the interval (one
  // per interval filled logs), the last one once.
  wo.progress_interactive = false;
  wo.progress_interval_s = 1e-6;
  const SequenceWriteSummary s = writeSequence(seq, dir, wo);
  ASSERT_TRUE(s.completed);
  EXPECT_EQ(s.frames, 37u);
  EXPECT_EQ(s.imu_samples, 1801u);
  const std::string log = progress.str();
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 10) << log;
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  EXPECT_EQ(log.rfind("rgbdi-sim: frame 4/37 (10.8 %)", 0), 0u) << log;
  EXPECT_EQ(log.find("rgbdi-sim: frame 37/37 (100.0 %)"), log.rfind("rgbdi-sim: frame ")) << log;
  for (const char* f : {"sequence.rawlog", "groundtruth.tum", "groundtruth_cam.tum", "config.ini",
                        "simulation.ini", "sequence.bag"})
    EXPECT_TRUE(fs::exists(dir + "/" + f)) << f;
  // 37 colour PNGs and 37 depth files.
  EXPECT_EQ(
      std::distance(fs::directory_iterator(dir + "/sequence_Images"), fs::directory_iterator{}),
      74);

  // --- the rawlog, read back with the project's reader, equals the in-process stream.
  io::RawlogSource src(s.rawlog_path);
  io::Measurement m;
  std::size_t imu = 0, frames = 0;
  double last = -1.0;
  while (src.next(m)) {
    const double t = io::measurementTime(m);
    EXPECT_GE(t, last);
    last = t;
    if (io::isImu(m)) {
      const ImuSample& a = std::get<ImuSample>(m);
      const ImuSample b = seq.imuSample(imu++);
      EXPECT_NEAR(a.t, b.t, 1e-6);  // MRPT timestamps have 100 ns ticks
      EXPECT_EQ(a.acc, b.acc);
      EXPECT_EQ(a.gyr, b.gyr);
    } else {
      const RgbdFrame& a = std::get<RgbdFrame>(m);
      const RgbdFrame b = seq.renderFrame(frames++);
      EXPECT_NEAR(a.t, b.t, 1e-6);
      EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0);  // PNG is lossless
      ASSERT_EQ(a.depth.type(), CV_16UC1);
      EXPECT_DOUBLE_EQ(a.depth_unit_m, 1e-3);
      EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0);
      EXPECT_TRUE(a.depth_aligned_to_color);
      EXPECT_DOUBLE_EQ(a.cam_color.fx, b.cam_color.fx);
      EXPECT_DOUBLE_EQ(a.cam_depth.cx, b.cam_depth.cx);
      EXPECT_TRUE(a.source_T_body_cam.isApprox(seq.options().extrinsic.T_body_cam, 1e-9));
    }
  }
  EXPECT_EQ(imu, seq.imuCount());
  EXPECT_EQ(frames, seq.frameCount());

  // --- ground truth files.
  const auto gt = readTumLines(s.groundtruth_path);
  ASSERT_EQ(gt.size(), seq.imuCount());
  const Eigen::Isometry3d T = seq.groundTruth(1004.0).T_world_body;
  EXPECT_DOUBLE_EQ(gt[800][0], 1004.0);
  EXPECT_NEAR(gt[800][1], T.translation().x(), 1e-12);
  EXPECT_NEAR(std::abs(gt[800][7]), std::abs(Eigen::Quaterniond(T.rotation()).w()), 1e-12);
  const auto gt_cam = readTumLines(s.groundtruth_cam_path);
  ASSERT_EQ(gt_cam.size(), seq.frameCount());
  EXPECT_NEAR(gt_cam[8][0], 1002.0 - 0.015, 1e-9);  // image stamp; pose at exposure 1002 s
  EXPECT_NEAR(gt_cam[8][3], seq.cameraPose(1002.0).translation().z(), 1e-12);

  // --- config.ini: loadable by rgbdi-slam's loaders, nothing unknown, inflated noise.
  IniReader ini = IniReader::fromFile(s.config_path);
  const CameraOptions cam = CameraOptions::load(ini);
  const ImuOptions imu_opt = ImuOptions::load(ini);
  const ExtrinsicOptions ext = ExtrinsicOptions::load(ini);
  ini.acceptConfigSectionsExcept({"camera", "imu", "extrinsic"});
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
  EXPECT_DOUBLE_EQ(cam.camera.fx, CameraOptions().camera.fx);
  EXPECT_EQ(cam.camera.width, 640);
  EXPECT_DOUBLE_EQ(imu_opt.acc_noise_density, 2.0 * 0.02);
  EXPECT_DOUBLE_EQ(imu_opt.gyr_noise_density, 2.0 * 0.002);
  EXPECT_DOUBLE_EQ(imu_opt.acc_random_walk, 2.0 * 4e-4);
  EXPECT_DOUBLE_EQ(imu_opt.gyr_random_walk, 2.0 * 2e-5);
  EXPECT_DOUBLE_EQ(imu_opt.gravity_m_s2, 9.81);
  EXPECT_DOUBLE_EQ(imu_opt.rate_hz, 200.0);
  EXPECT_TRUE(ext.T_body_cam.isApprox(seq.options().extrinsic.T_body_cam, 1e-12));
  EXPECT_DOUBLE_EQ(ext.time_offset_s, 0.0);  // a user does not know the true 15 ms
  EXPECT_NE(slurp(s.config_path).find("config_noise_inflation = 2"), std::string::npos);

  // --- simulation.ini regenerates the same sequence.
  IniReader settings = IniReader::fromFile(s.simulation_path);
  SimOptions again = SimOptions::load(settings);
  settings.checkNoUnknownKeys();
  again.profile.kind = ProfileKind::WheeledCircle;
  const SimulatedSequence seq2(again);
  EXPECT_EQ(seq2.frameCount(), seq.frameCount());
  EXPECT_EQ(seq2.imuSample(1234).acc, seq.imuSample(1234).acc);
  EXPECT_DOUBLE_EQ(seq2.frameStamp(3), seq.frameStamp(3));

  // --- the bag.
  rosbag::Bag bag(s.bag_path, rosbag::bagmode::Read);
  rosbag::View view(bag);
  std::map<std::string, int> count;
  for (const rosbag::MessageInstance& msg : view) {
    ++count[msg.getTopic()];
    if (auto img = msg.instantiate<sensor_msgs::Image>()) {
      EXPECT_EQ(img->encoding, msg.getTopic() == "/camera/color/image_raw" ? "rgb8" : "16UC1");
    }
  }
  EXPECT_EQ(count["/camera/color/image_raw"], 37);
  EXPECT_EQ(count["/camera/aligned_depth_to_color/image_raw"], 37);
  EXPECT_EQ(count["/camera/imu"], 1801);
  EXPECT_EQ(count["/vrpn_client_node/rgbdi/pose"], 1801);
}

TEST(SequenceWriter, SameSeedGivesByteIdenticalOutputDifferentSeedDoesNot) {
  const std::string a = test::makeTempDir("simseq"), b = test::makeTempDir("simseq"),
                    c = test::makeTempDir("simseq");
  writeSequence(SimulatedSequence(shortOptions(5)), a, SequenceWriterOptions{});
  writeSequence(SimulatedSequence(shortOptions(5)), b, SequenceWriterOptions{});
  writeSequence(SimulatedSequence(shortOptions(6)), c, SequenceWriterOptions{});
  const auto ta = tree(a), tb = tree(b), tc = tree(c);
  ASSERT_EQ(ta.size(), tb.size());
  for (const auto& [name, bytes] : ta) EXPECT_TRUE(bytes == tb.at(name)) << name << " differs";
  EXPECT_TRUE(ta.at("sequence.rawlog") != tc.at("sequence.rawlog"));
  EXPECT_TRUE(ta.at("sequence_Images/RGBD_3_depth.bin") !=
              tc.at("sequence_Images/RGBD_3_depth.bin"));
  EXPECT_TRUE(ta.at("groundtruth.tum") == tc.at("groundtruth.tum"));  // same motion
}

TEST(SequenceWriter, StoppingEarlyLeavesNoRawlog) {
  const std::string dir = test::makeTempDir("simseq");
  std::atomic<bool> stop{true};
  const SequenceWriteSummary s = writeSequence(SimulatedSequence(shortOptions()), dir, {}, &stop);
  EXPECT_FALSE(s.completed);
  EXPECT_FALSE(fs::exists(s.rawlog_path));
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(SequenceWriter, UnwritableDirectoryIsAClearError) {
  const std::string dir = test::makeTempDir("simseq");
  std::ofstream(dir + "/file") << "x";
  try {
    writeSequence(SimulatedSequence(shortOptions()), dir + "/file/sub", {});
    ADD_FAILURE() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/file/sub"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::sim
