// End-to-end: the rawlog-convert app on the real OpenNI2 rawlog and on generated rawlogs.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/io/stream_options.h"
#include "testing/fixtures.h"

namespace {

namespace fs = std::filesystem;
using rgbdi::test::runCommand;

std::string app() { return rgbdi::test::binDir() + "/rawlog-convert"; }

class RawlogConvertInfo : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = rgbdi::test::makeTempDir("rgbdi_convert_info"); }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  /// 2 s of IMU at 200 Hz reported in g, one duplicated sample, frames at 10 Hz.
  std::string writeSequence(const std::string& name) {
    rgbdi::io::RawlogWriterOptions o;
    o.T_body_cam = rgbdi::io::StreamConfig().extrinsic.T_body_cam;
    rgbdi::io::RawlogWriter w(dir_ + "/" + name, o);
    const double t0 = 1700000000.0;
    for (int i = 0; i <= 400; ++i) {
      rgbdi::ImuSample s;
      s.t = t0 + 0.005 * i;
      s.acc = Eigen::Vector3d(0.0, 0.0, 1.0);  // g units
      w.write(s);
      if (i == 100) w.write(s);
      if (i % 20 == 10) {
        rgbdi::RgbdFrame f;
        f.t = s.t + 0.001;
        f.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(50, 60, 70));
        f.depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(1200));
        f.cam_color.width = 32;
        f.cam_color.height = 24;
        f.cam_color.fx = f.cam_color.fy = 30;
        f.cam_color.cx = 16;
        f.cam_color.cy = 12;
        f.cam_depth = f.cam_color;
        w.write(f);
      }
    }
    w.close();
    return dir_ + "/" + name;
  }
  std::string dir_;
};

TEST_F(RawlogConvertInfo, HelpAndUsageErrors) {
  std::string out;
  EXPECT_EQ(runCommand(app() + " --help", &out), 0);
  EXPECT_NE(out.find("--info FILE"), std::string::npos) << out;
  EXPECT_NE(out.find("--json"), std::string::npos);
  EXPECT_NE(out.find("Exit status: 0 success"), std::string::npos);
  EXPECT_EQ(runCommand(app(), &out), 2);
  EXPECT_NE(out.find("nothing to do"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app() + " --frobnicate", &out), 2);
  EXPECT_NE(out.find("unknown option '--frobnicate'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app() + " --info", &out), 2);
  EXPECT_NE(out.find("--info needs a value"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app() + " -i " + dir_ + "/in.bag -o " + dir_ + "/out.rawlog", &out), 1);
  EXPECT_NE(out.find(dir_ + "/in.bag: no such file or directory"), std::string::npos) << out;
}

TEST_F(RawlogConvertInfo, RealOpenNi2Rawlog) {
  const std::string path = rgbdi::test::fixturePath("real/openni2_single_rgbd.rawlog");
  RGBDI_REQUIRE_FIXTURE(path);
  std::string out;
  ASSERT_EQ(runCommand(app() + " --info '" + path + "'", &out), 0) << out;
  EXPECT_NE(out.find("Records: 1 (observations 1, actions 0, unusable 0)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("RGB-D: 1 frames"), std::string::npos) << out;
  EXPECT_NE(out.find("with colour 1, with depth 1, depth aligned to colour 0; depth unit 0.001 m, "
                     "median depth 2.040 m"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find(path + " record 0: no IMU samples"), std::string::npos) << out;
  EXPECT_NE(out.find(path + " record 0: the rawlog's sensorPose places the colour camera"),
            std::string::npos)
      << out;

  ASSERT_EQ(runCommand(app() + " --json --info '" + path + "' 2>/dev/null", &out), 0) << out;
  const auto j = nlohmann::json::parse(out);
  EXPECT_EQ(j["images"]["delivered"], 1);
  EXPECT_EQ(j["imu"]["delivered"], 0);
  EXPECT_EQ(j["extrinsic_mismatch"], true);
  EXPECT_EQ(j["ok"], true);
  EXPECT_EQ(j["warnings"].size(), 2u);
}

TEST_F(RawlogConvertInfo, GeneratedRawlogWithProblems) {
  const std::string path = writeSequence("gen.rawlog");
  std::string out;
  ASSERT_EQ(runCommand(app() + " --info " + path, &out), 0) << out;
  EXPECT_NE(out.find("IMU:   401 samples, 2.000 s"), std::string::npos) << out;
  EXPECT_NE(out.find(", 200.00 Hz"), std::string::npos) << out;
  EXPECT_NE(out.find("RGB-D: 20 frames, 1.900 s"), std::string::npos) << out;
  EXPECT_NE(out.find("mean |acc| 1.000 m/s^2 (looks like g units!)"), std::string::npos) << out;
  EXPECT_NE(out.find("order: non-monotonic 0, reordered 0, duplicates dropped 1, late dropped 0"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("IMU stamp t = 1700000000.500000 s duplicates an earlier IMU stamp; dropped"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("sensorPose vs [extrinsic] agree"), std::string::npos) << out;

  // A config that tightens nothing but renames nothing is accepted; a bad one is a usage error.
  const std::string cfg = dir_ + "/c.ini";
  std::ofstream(cfg) << "[imu]\nrate_hz = 100\n";
  ASSERT_EQ(runCommand(app() + " --info " + path + " --config " + cfg, &out), 0) << out;
  EXPECT_NE(out.find("measured IMU rate 200.0 Hz differs from [imu] rate_hz = 100 Hz"),
            std::string::npos)
      << out;
  std::ofstream(cfg) << "[stream]\nimu_gap_factor = -1\n";
  EXPECT_EQ(runCommand(app() + " --info " + path + " --config " + cfg, &out), 2);
  EXPECT_NE(out.find(cfg + " [stream] imu_gap_factor: value -1 is out of the accepted range"),
            std::string::npos)
      << out;
}

TEST_F(RawlogConvertInfo, DamagedInputExitsWithThreeUnreadableWithOne) {
  const std::string path = writeSequence("cut.rawlog");
  fs::resize_file(path, fs::file_size(path) / 2 + 7);  // inside a record (half is a boundary)
  std::string out;
  EXPECT_EQ(runCommand(app() + " --info " + path, &out), 3);
  EXPECT_NE(out.find("ERROR: " + path + " record "), std::string::npos) << out;
  EXPECT_NE(out.find(": truncated: the file ends inside this record"), std::string::npos) << out;
  EXPECT_EQ(runCommand(app() + " --info " + dir_ + "/none.rawlog", &out), 1);
  EXPECT_NE(out.find(dir_ + "/none.rawlog: no such file or directory"), std::string::npos) << out;
}

TEST_F(RawlogConvertInfo, BagInfoListsTopicsAndLayout) {
  const std::string bag =
      rgbdi::test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  std::string out;
  EXPECT_EQ(runCommand(app() + " --info '" + bag + "'", &out), 0) << out;
  EXPECT_NE(out.find("Layout: RealSense SDK recording layout"), std::string::npos) << out;
  EXPECT_NE(out.find("/device_0/sensor_0/Depth_0/image/data"), std::string::npos) << out;
}

// MRPT's own tool must read what RawlogWriter produces (both layouts, gzip).
TEST_F(RawlogConvertInfo, MrptRawlogEditReadsOurRawlogs) {
  if (!fs::exists("/usr/bin/rawlog-edit")) GTEST_SKIP() << "rawlog-edit not installed";
  const std::string path = writeSequence("for_mrpt.rawlog");
  std::string out;
  ASSERT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + path, &out), 0) << out;
  EXPECT_NE(out.find("Overall number of objects         : 422"), std::string::npos) << out;
  EXPECT_NE(out.find("Observations format               : Yes"), std::string::npos) << out;
  EXPECT_NE(out.find("IMU /    402 /"), std::string::npos) << out;
  EXPECT_NE(out.find("RGBD /     20 /"), std::string::npos) << out;

  rgbdi::io::RawlogWriterOptions o;
  o.layout = rgbdi::io::RawlogWriterOptions::Layout::SensoryFrames;
  o.gzip = true;
  const std::string sf = dir_ + "/sf.rawlog.gz";
  {
    rgbdi::io::RawlogWriter w(sf, o);
    for (int i = 0; i < 5; ++i) {
      rgbdi::ImuSample s;
      s.t = 10.0 + 0.01 * i;
      w.write(s);
    }
    w.close();
  }
  ASSERT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + sf, &out), 0) << out;
  EXPECT_NE(out.find("Actions/SensoryFrame format       : Yes"), std::string::npos) << out;
  EXPECT_NE(out.find("Overall number of objects         : 10"), std::string::npos) << out;
}

}  // namespace
