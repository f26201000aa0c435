// End-to-end: rawlog-convert on a TUM RGB-D folder (generated here in the benchmark's layout):
// rawlog + ground truth, accepted by MRPT's rawlog-edit; --info on the folder; errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"

namespace {

namespace fs = std::filesystem;
using rgbdi::test::runCommand;

std::string app() { return rgbdi::test::binDir() + "/rawlog-convert"; }

class RawlogConvertTum : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = rgbdi::test::makeTempDir("rgbdi_convert_tum");
    dir_ = root_ + "/rgbd_dataset_freiburg3_unit";
    fs::create_directories(dir_ + "/rgb");
    fs::create_directories(dir_ + "/depth");
    std::ofstream rgb(dir_ + "/rgb.txt"), depth(dir_ + "/depth.txt"),
        acc(dir_ + "/accelerometer.txt"), gt(dir_ + "/groundtruth.txt");
    rgb << "# color images\n# timestamp filename\n" << std::fixed << std::setprecision(6);
    depth << "# depth maps\n# timestamp filename\n" << std::fixed << std::setprecision(6);
    acc << "# accelerometer data\n# timestamp ax ay az\n" << std::fixed << std::setprecision(4);
    gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
       << std::fixed << std::setprecision(4);
    cv::Mat colour(480, 640, CV_8UC3);
    cv::randu(colour, 0, 256);
    for (int k = 0; k < 10; ++k) {
      const double t = 1341847980.0 + k / 30.0;
      char name[64];
      std::snprintf(name, sizeof name, "rgb/%.6f.png", t);
      rgb << t << " " << name << "\n";
      cv::imwrite(dir_ + "/" + name, colour);
      std::snprintf(name, sizeof name, "depth/%.6f.png", t + 0.011);
      depth << t + 0.011 << " " << name << "\n";
      cv::imwrite(dir_ + "/" + name, cv::Mat(480, 640, CV_16UC1, cv::Scalar(10000 + 50 * k)));
    }
    for (int k = 0; k < 40; ++k) {
      const double t = 1341847980.0 + 0.01 * k;
      acc << t << " 0.1 -9.7 0.3\n";
      gt << t << " " << 0.001 * k << " 0.2 1.4 0.0 0.0 0.0 1.0\n";
    }
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(root_, ec);
  }
  std::string root_, dir_;
};

TEST_F(RawlogConvertTum, ConvertsFolderToRawlogAndGroundTruth) {
  const std::string rawlog = root_ + "/tum.rawlog";
  std::string out;
  ASSERT_EQ(runCommand(app() + " " + dir_ + " -o " + rawlog + " --quiet", &out), 0) << out;
  EXPECT_NE(out.find("TUM RGB-D folder"), std::string::npos) << out;
  EXPECT_NE(out.find("colour intrinsics: TUM fr3 calibration (detected from the folder name)"),
            std::string::npos)
      << out;
  EXPECT_NE(
      out.find(
          "Written: 10 RGB-D observations (10 colour+depth, 0 depth-only), 40 IMU observations, 40 "
          "ground-truth poses"),
      std::string::npos)
      << out;
  EXPECT_NE(out.find("TUM RGB-D has no gyroscope"), std::string::npos) << out;

  rgbdi::io::RawlogSource src(rawlog);
  src.logging_enable_console_output = false;
  rgbdi::io::Measurement m;
  std::size_t frames = 0;
  while (src.next(m)) {
    const auto& f = std::get<rgbdi::RgbdFrame>(m);  // the accelerometer-only records are not usable
    EXPECT_DOUBLE_EQ(f.depth_unit_m, 0.0002);
    EXPECT_NEAR(f.depthAt(100, 100), 2.0 + 0.01 * static_cast<double>(frames), 1e-12);
    EXPECT_DOUBLE_EQ(f.cam_color.fx, 535.4);
    EXPECT_TRUE(f.depth_aligned_to_color);
    ++frames;
  }
  EXPECT_EQ(frames, 10u);
  EXPECT_EQ(src.diagnostics().unusable, 40u);

  const rgbdi::Trajectory gt = rgbdi::eval::readTum(root_ + "/tum_groundtruth.tum");
  ASSERT_EQ(gt.size(), 40u);
  EXPECT_DOUBLE_EQ(gt[5].p.x(), 0.005);

  if (fs::exists("/usr/bin/rawlog-edit")) {
    ASSERT_EQ(runCommand("/usr/bin/rawlog-edit --info -i " + rawlog, &out), 0) << out;
    EXPECT_NE(out.find("RGBD /     10 /"), std::string::npos) << out;
    EXPECT_NE(out.find("IMU /     40 /"), std::string::npos) << out;
  }
}

TEST_F(RawlogConvertTum, InfoAndErrors) {
  std::string out;
  ASSERT_EQ(runCommand(app() + " --info " + dir_, &out), 0) << out;
  EXPECT_NE(out.find("rgb.txt               10 entries"), std::string::npos) << out;
  EXPECT_NE(out.find("Camera: fr3 (from the folder name)"), std::string::npos) << out;
  EXPECT_NE(out.find("TUM RGB-D has no gyroscope"), std::string::npos) << out;

  EXPECT_EQ(runCommand(app() + " " + dir_ + " -o " + root_ + "/x.rawlog --tum-camera fr9", &out),
            2);
  EXPECT_NE(out.find("unknown TUM camera 'fr9'"), std::string::npos) << out;
  std::ofstream(dir_ + "/rgb.txt", std::ios::app) << "1341847990.0\n";
  EXPECT_EQ(runCommand(app() + " " + dir_ + " -o " + root_ + "/x.rawlog", &out), 1);
  EXPECT_NE(out.find(dir_ + "/rgb.txt line 13: expected 'timestamp filename'"), std::string::npos)
      << out;
}

}  // namespace
