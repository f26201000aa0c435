// End-to-end: rawlog-convert on ROS1 bags.
// * Bags written by rgbdi-sim (dataset layout; uncompressed, bz2, lz4) convert to exactly the
//   simulator's own rawlog: byte for byte, image files included, and observation by observation;
//   the ground truth equals the simulator's.
// * The output is accepted by MRPT's rawlog-edit and by rgbdi-slam (with the OUT.ini written
//   from a VINS yaml).
// * The real RealSense SDK recording; a truncated bag; usage and data errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"

namespace {

namespace fs = std::filesystem;
using rgbdi::test::runCommand;

std::string app(const std::string& name) { return rgbdi::test::binDir() + "/" + name; }

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<rgbdi::io::Measurement> readAll(const std::string& rawlog) {
  rgbdi::io::RawlogSource src(rawlog);
  src.logging_enable_console_output = false;
  std::vector<rgbdi::io::Measurement> all;
  rgbdi::io::Measurement m;
  while (src.next(m)) all.push_back(m);
  return all;
}

/// Simulated sequences with bags, each generated the first time a test of this process needs it
/// (ctest runs every test in its own process).
class RawlogConvertBag : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = new std::string(rgbdi::test::makeTempDir("rgbdi_convert_bag"));
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(*root_, ec);
    delete root_;
  }
  /// "lz4": 10 s wheeled robot at 15 Hz; "none" / "bz2": 8 s hand-held at 5 Hz.
  static std::string seq(const std::string& name) {
    const std::string dir = *root_ + "/" + name;
    if (!fs::exists(dir + "/sequence.bag")) {
      const std::string args = name == "lz4" ? "--profile wheeled_circle --duration 10 --fps 15"
                                             : "--profile handheld --duration 8 --fps 5";
      std::string out;
      const int rc = runCommand(
          app("rgbdi-sim") + " " + args + " --bag --bag-compression " + name + " --out " + dir,
          &out);
      EXPECT_EQ(rc, 0) << out;
    }
    return dir;
  }
  static std::string* root_;
};
std::string* RawlogConvertBag::root_ = nullptr;

TEST_F(RawlogConvertBag, SimulatorBagsConvertToTheSimulatorsRawlog) {
  for (const char* name : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(name);
    const std::string dir = seq(name);
    const std::string out_rawlog = dir + "/converted.rawlog";
    std::string out;
    ASSERT_EQ(runCommand(app("rawlog-convert") + " " + dir + "/sequence.bag -o " + out_rawlog +
                             " --config " + dir + "/config.ini --external-images --quiet",
                         &out),
              0)
        << out;
    EXPECT_NE(out.find("ROS1 bag, VINS-RGBD dataset layout"), std::string::npos) << out;

    // Same bytes: the rawlog and every image file.
    EXPECT_TRUE(slurp(out_rawlog) == slurp(dir + "/sequence.rawlog"));
    std::size_t images = 0;
    for (const auto& e : fs::directory_iterator(dir + "/sequence_Images")) {
      const fs::path mine = fs::path(dir) / "converted_Images" / e.path().filename();
      ASSERT_TRUE(fs::exists(mine)) << mine;
      EXPECT_TRUE(slurp(mine.string()) == slurp(e.path().string())) << mine;
      ++images;
    }
    EXPECT_EQ(images,
              static_cast<std::size_t>(std::distance(
                  fs::directory_iterator(dir + "/converted_Images"), fs::directory_iterator{})));

    // Observation by observation (what rgbdi-slam reads).
    const auto a = readAll(out_rawlog), b = readAll(dir + "/sequence.rawlog");
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GT(a.size(), 500u);
    for (std::size_t i = 0; i < a.size(); ++i) {
      ASSERT_EQ(a[i].index(), b[i].index()) << i;
      if (const auto* fa = std::get_if<rgbdi::RgbdFrame>(&a[i])) {
        const auto& fb = std::get<rgbdi::RgbdFrame>(b[i]);
        EXPECT_DOUBLE_EQ(fa->t, fb.t) << i;
        EXPECT_EQ(cv::countNonZero(fa->depth != fb.depth), 0) << i;
        EXPECT_EQ(cv::countNonZero(cv::Mat(fa->rgb != fb.rgb).reshape(1)), 0) << i;
        EXPECT_DOUBLE_EQ(fa->depth_unit_m, fb.depth_unit_m);
        EXPECT_DOUBLE_EQ(fa->cam_color.fx, fb.cam_color.fx);
        EXPECT_DOUBLE_EQ(fa->cam_depth.cy, fb.cam_depth.cy);
        EXPECT_EQ(fa->depth_aligned_to_color, fb.depth_aligned_to_color);
        EXPECT_TRUE(fa->source_T_body_cam.isApprox(fb.source_T_body_cam, 1e-12)) << i;
      } else {
        const auto& ia = std::get<rgbdi::ImuSample>(a[i]);
        const auto& ib = std::get<rgbdi::ImuSample>(b[i]);
        EXPECT_DOUBLE_EQ(ia.t, ib.t) << i;
        EXPECT_EQ(ia.acc, ib.acc) << i;
        EXPECT_EQ(ia.gyr, ib.gyr) << i;
      }
    }

    // Ground truth: the body pose at every IMU sample, like the simulator's groundtruth.tum.
    const rgbdi::Trajectory gt = rgbdi::eval::readTum(dir + "/converted_groundtruth.tum");
    const rgbdi::Trajectory ref = rgbdi::eval::readTum(dir + "/groundtruth.tum");
    ASSERT_EQ(gt.size(), ref.size());
    for (std::size_t i = 0; i < gt.size(); ++i) {
      EXPECT_NEAR(gt[i].t, ref[i].t, 1e-9);
      EXPECT_LT((gt[i].p - ref[i].p).norm(), 1e-12) << i;
      EXPECT_LT(gt[i].q.angularDistance(ref[i].q), 1e-9) << i;
    }

    if (fs::exists("/usr/bin/rawlog-edit")) {
      ASSERT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + out_rawlog, &out), 0) << out;
      EXPECT_NE(out.find("Observations format               : Yes"), std::string::npos) << out;
    }
  }
}

TEST_F(RawlogConvertBag, RgbdiSlamRunsWithTheConfigWrittenFromAVinsYaml) {
  const std::string dir = seq("lz4");
  // rgbdi-sim --bag writes the bag's VINS-RGBD calibration next to it: the simulator's camera,
  // extrinsic and (inflated) noise as a VINS-RGBD user would have them.
  ASSERT_TRUE(fs::exists(dir + "/vins_config.yaml"));
  rgbdi::IniReader sim_cfg = rgbdi::IniReader::fromFile(dir + "/config.ini");
  const rgbdi::ImuOptions imu = rgbdi::ImuOptions::load(sim_cfg);
  const rgbdi::ExtrinsicOptions ext = rgbdi::ExtrinsicOptions::load(sim_cfg);

  std::string out;
  const std::string rawlog = dir + "/vins.rawlog";
  ASSERT_EQ(runCommand(app("rawlog-convert") + " " + dir + "/sequence.bag --out " + rawlog +
                           " --camera-yaml " + dir + "/vins_config.yaml --quiet",
                       &out),
            0)
      << out;
  EXPECT_NE(out.find("vins.ini (rgbdi configuration from"), std::string::npos) << out;
  // The written configuration carries the yaml's values back.
  rgbdi::IniReader ini = rgbdi::IniReader::fromFile(dir + "/vins.ini");
  const rgbdi::ImuOptions imu2 = rgbdi::ImuOptions::load(ini);
  EXPECT_NEAR(imu2.acc_noise_density, imu.acc_noise_density, 1e-12);
  EXPECT_NEAR(imu2.gyr_random_walk, imu.gyr_random_walk, 1e-14);
  EXPECT_DOUBLE_EQ(imu2.rate_hz, 200.0);
  EXPECT_TRUE(rgbdi::ExtrinsicOptions::load(ini).T_body_cam.isApprox(ext.T_body_cam, 1e-12));

  ASSERT_EQ(
      runCommand(app("rgbdi-slam") + " --input " + rawlog + " --out " + dir + "/slam --config " +
                     dir + "/vins.ini --gt " + dir + "/vins_groundtruth.tum --quiet",
                 &out),
      0)
      << out;
  std::ifstream summary(dir + "/slam/summary.json");
  const auto j = nlohmann::json::parse(summary);
  EXPECT_LT(j["evaluation"]["ate_rmse"].get<double>(), 0.05) << j.dump(2);
  EXPECT_GT(j["evaluation"]["coverage"].get<double>(), 0.8) << j.dump(2);
}

TEST_F(RawlogConvertBag, TruncatedBagLeavesAValidRawlogOfWhatCameBefore) {
  const std::string dir = seq("none");
  const std::string cut = dir + "/cut.bag";
  fs::copy_file(dir + "/sequence.bag", cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(cut) * 2 / 5);
  std::string out;
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + cut + " -o " + dir + "/cut.rawlog --config " +
                           dir + "/config.ini --quiet",
                       &out),
            3);  // damaged input, converted up to the damage
  EXPECT_NE(
      out.find("rawlog-convert: " + cut + ": truncated: the file ends inside the chunk at byte "),
      std::string::npos)
      << out;
  EXPECT_NE(out.find("the file is truncated"), std::string::npos) << out;
  const auto all = readAll(dir + "/cut.rawlog");
  std::size_t frames = 0;
  for (const auto& m : all) frames += std::holds_alternative<rgbdi::RgbdFrame>(m) ? 1 : 0;
  EXPECT_GT(frames, 10u);  // about 2/5 of 41
  EXPECT_LT(frames, 25u);
  if (fs::exists("/usr/bin/rawlog-edit")) {
    EXPECT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + dir + "/cut.rawlog", &out), 0) << out;
  }
  // --info on the damaged bag describes what is readable and exits with 3.
  EXPECT_EQ(runCommand(app("rawlog-convert") + " --info " + cut, &out), 3);
  EXPECT_NE(out.find("index unreadable"), std::string::npos) << out;
}

TEST_F(RawlogConvertBag, RealSenseRecording) {
  const std::string bag =
      rgbdi::test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  const std::string rawlog = *root_ + "/rs.rawlog.gz";
  std::string out;
  ASSERT_EQ(runCommand(app("rawlog-convert") + " '" + bag + "' -o " + rawlog, &out), 0) << out;
  EXPECT_NE(
      out.find("Written: 2 RGB-D observations (0 colour+depth, 2 depth-only), 0 IMU observations"),
      std::string::npos)
      << out;
  EXPECT_NE(out.find("1 colour image(s) without a depth image within 0.020 s"), std::string::npos)
      << out;
  EXPECT_NE(out.find("rawlog-convert: [####################] 100.0 %"), std::string::npos)
      << out;  // progress
  const auto all = readAll(rawlog);
  ASSERT_EQ(all.size(), 2u);
  for (const auto& m : all) {
    const auto& f = std::get<rgbdi::RgbdFrame>(m);
    EXPECT_FALSE(f.hasColor());
    EXPECT_NEAR(f.cam_depth.fx, 390.43, 0.005);
    EXPECT_NEAR(f.cam_depth.cx, 331.39, 0.005);
    EXPECT_NEAR(f.cam_color.fx, 613.20, 0.005);
    EXPECT_DOUBLE_EQ(f.depth_unit_m, 0.001);
    EXPECT_FALSE(f.depth_aligned_to_color);
    // The SDK's depth -> colour extrinsic (p_color = R p_depth + t), through the rawlog.
    EXPECT_NEAR(f.T_color_depth.translation().x(), 0.014311, 1e-6);
    EXPECT_NEAR(f.T_color_depth.translation().y(), 0.000602, 1e-6);
    EXPECT_NEAR(f.T_color_depth.translation().z(), 0.000611, 1e-6);
    EXPECT_NEAR(f.T_color_depth.linear()(0, 2), 0.012926, 1e-6);
  }
  if (fs::exists("/usr/bin/rawlog-edit")) {
    ASSERT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + rawlog, &out), 0) << out;
    EXPECT_NE(out.find("RGBD /      2 /"), std::string::npos) << out;
  }
  ASSERT_EQ(runCommand(app("rawlog-convert") + " --info '" + bag + "' --json 2>/dev/null", &out), 0)
      << out;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["topics"].size(), 70u);
  EXPECT_EQ(j["layout"]["kind"], "RealSense SDK recording layout");
  EXPECT_EQ(j["layout"]["depth"], "/device_0/sensor_0/Depth_0/image/data");
  EXPECT_EQ(j["indexed"], true);
}

TEST_F(RawlogConvertBag, UsageAndDataErrors) {
  const std::string bag = seq("none") + "/sequence.bag";
  const std::string o = " -o " + *root_ + "/e.rawlog";
  std::string out;
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + bag + " -o " + *root_ + "/e.txt", &out), 2);
  EXPECT_NE(out.find("must end in .rawlog or .rawlog.gz"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + bag + o + " --depth-aligned maybe", &out), 2);
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + bag, &out), 2);
  EXPECT_NE(out.find("no output given"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + seq("none") + "/sequence.rawlog" + o, &out),
            2);
  EXPECT_NE(out.find("is already an MRPT rawlog"), std::string::npos) << out;
  // A missing topic lists the topics that exist; nothing is written.
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + bag + o + " --imu-topic /imu0 --quiet", &out),
            1);
  EXPECT_NE(out.find("IMU topic '/imu0' is not in the bag; its topics are:"), std::string::npos)
      << out;
  EXPECT_NE(out.find("/camera/aligned_depth_to_color/image_raw"), std::string::npos) << out;
  EXPECT_NE(out.find("geometry_msgs/PoseStamped"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(*root_ + "/e.rawlog"));
  // A configuration error names the file and key.
  std::ofstream(*root_ + "/bad.ini") << "[convert]\npair_tolerance_s = 7\n";
  EXPECT_EQ(
      runCommand(app("rawlog-convert") + " " + bag + o + " --config " + *root_ + "/bad.ini", &out),
      2);
  EXPECT_NE(out.find("[convert] pair_tolerance_s"), std::string::npos) << out;
}

}  // namespace
