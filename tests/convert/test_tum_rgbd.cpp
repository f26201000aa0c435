// TUM RGB-D folders: camera presets and detection, list parsing with errors naming file and line,
// conversion of a small generated folder (pairing, depth factor 5000, accelerometer-only samples,
// ground truth, a missing image reported).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/convert/tum_rgbd.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;
using test::RecordingSink;

/// A TUM-style folder: 6 colour images at 30 Hz, depth 8 ms later (one depth missing), a
/// missing colour file, accelerometer at 100 Hz, ground truth at 100 Hz.
std::string makeFolder(const std::string& parent) {
  const std::string dir = parent + "/rgbd_dataset_freiburg1_unit";
  fs::create_directories(dir + "/rgb");
  fs::create_directories(dir + "/depth");
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt"), acc(dir + "/accelerometer.txt"),
      gt(dir + "/groundtruth.txt");
  rgb << "# color images\n# file: 'unit.bag'\n# timestamp filename\n";
  depth << "# depth maps\n# file: 'unit.bag'\n# timestamp filename\n";
  acc << "# accelerometer data\n# timestamp ax ay az\n";
  gt << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
  char name[64];
  for (int k = 0; k < 6; ++k) {
    const double t = 1305031102.0 + k / 30.0;
    std::snprintf(name, sizeof name, "rgb/%.6f.png", t);
    rgb << std::fixed << std::setprecision(6) << t << " " << name << "\n";
    if (k != 5)
      cv::imwrite(dir + "/" + name,
                  cv::Mat(480, 640, CV_8UC3, cv::Scalar(10 * k, 100, 200)));  // BGR
    if (k == 2) continue;  // no depth for this one
    const double td = t + 0.008;
    std::snprintf(name, sizeof name, "depth/%.6f.png", td);
    depth << std::fixed << std::setprecision(6) << td << " " << name << "\n";
    cv::imwrite(dir + "/" + name, cv::Mat(480, 640, CV_16UC1, cv::Scalar(5000 + 1000 * k)));
  }
  for (int k = 0; k < 20; ++k) {
    const double t = 1305031101.99 + 0.01 * k;
    acc << std::fixed << std::setprecision(4) << t << " -0.0268 -9.6548 0.02" << k << "\n";
    gt << std::fixed << std::setprecision(4) << t << " " << 0.01 * k << " 0.5 1.5 0 0 0 1\n";
  }
  return dir;
}

TEST(TumRgbd, CameraPresetsAndDetection) {
  const PinholeCamera fr1 = tumCamera("fr1");
  EXPECT_DOUBLE_EQ(fr1.fx, 517.3);
  EXPECT_DOUBLE_EQ(fr1.cy, 255.3);
  EXPECT_DOUBLE_EQ(fr1.dist[4], 1.1633);
  EXPECT_DOUBLE_EQ(tumCamera("fr2").fx, 520.9);
  EXPECT_DOUBLE_EQ(tumCamera("fr3").fy, 539.2);
  EXPECT_FALSE(tumCamera("fr3").hasDistortion());
  EXPECT_DOUBLE_EQ(tumCamera("ros").cx, 319.5);
  EXPECT_THROW(tumCamera("fr4"), std::invalid_argument);
  EXPECT_EQ(detectTumCamera("/data/rgbd_dataset_freiburg2_desk"), "fr2");
  EXPECT_EQ(detectTumCamera("/data/fr3_office/"), "fr3");
  EXPECT_EQ(detectTumCamera("/data/my_sequence"), "");
}

TEST(TumRgbd, ListErrorsNameFileAndLine) {
  const std::string dir = test::makeTempDir("tum");
  std::ofstream(dir + "/rgb.txt") << "# header\n1.0 rgb/a.png\n2.0\n";
  try {
    readTumImageList(dir + "/rgb.txt");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  dir + "/rgb.txt line 3: expected 'timestamp filename', got 1 fields"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir + "/depth.txt") << "x1.5 depth/a.png\n";
  EXPECT_THROW(readTumImageList(dir + "/depth.txt"), IoError);
  EXPECT_THROW(readTumImageList(dir + "/none.txt"), IoError);
}

TEST(TumRgbd, ConvertsAGeneratedFolder) {
  const std::string dir = makeFolder(test::makeTempDir("tum"));
  TumRgbdConverter conv(dir, bag::ConvertOptions(), "", bag::FallbackCalibration::defaults());
  EXPECT_DOUBLE_EQ(conv.camera().fx, 517.3);  // fr1 from the folder name
  EXPECT_TRUE(conv.T_body_cam().isApprox(Eigen::Isometry3d::Identity()));
  RecordingSink sink(RecordingSink::ImuKind::kAccelerometerOnly);
  std::vector<double> progress;
  const bag::ConversionReport r = conv.run(sink, [&](double f) { progress.push_back(f); });
  EXPECT_TRUE(r.ok()) << r.error;
  // Colour 0, 1, 3, 4 pair; colour 2 has no depth; colour 5's file is missing, so its depth is
  // written depth-only.
  ASSERT_EQ(sink.frames.size(), 5u);
  const int colour_index[4] = {0, 1, 3, 4};
  for (int i = 0; i < 4; ++i) {
    const RgbdFrame& f = sink.frames[static_cast<size_t>(i)];
    const int k = colour_index[i];
    EXPECT_NEAR(f.t, 1305031102.0 + k / 30.0, 1e-6);
    ASSERT_TRUE(f.hasColor());
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(10, 10), cv::Vec3b(200, 100, static_cast<uchar>(10 * k)));  // RGB
    EXPECT_EQ(f.depth.at<std::uint16_t>(10, 10), 5000 + 1000 * k);
    EXPECT_DOUBLE_EQ(f.depth_unit_m, 1.0 / 5000.0);
    EXPECT_NEAR(f.depthAt(10, 10), 1.0 + 0.2 * k, 1e-12);
    EXPECT_TRUE(f.depth_aligned_to_color);
    EXPECT_DOUBLE_EQ(f.cam_depth.fx, 517.3);
  }
  EXPECT_FALSE(sink.frames[4].hasColor());
  EXPECT_NEAR(sink.frames[4].t, 1305031102.0 + 5 / 30.0 + 0.008, 1e-6);
  EXPECT_EQ(r.pairing.pairs, 4u);
  EXPECT_EQ(r.pairing.color_alone, 1u);
  EXPECT_EQ(r.unreadable, 1u);
  ASSERT_EQ(sink.accel.size(), 20u);
  EXPECT_DOUBLE_EQ(sink.accel[3].second.y(), -9.6548);
  EXPECT_EQ(r.accel_only_samples, 20u);
  ASSERT_EQ(sink.poses.size(), 20u);
  EXPECT_DOUBLE_EQ(sink.poses[7].p.x(), 0.07);
  const std::string text = r.text();
  EXPECT_NE(text.find("TUM RGB-D has no gyroscope"), std::string::npos) << text;
  EXPECT_NE(text.find("missing or unreadable image"), std::string::npos) << text;
  ASSERT_FALSE(progress.empty());
  EXPECT_DOUBLE_EQ(progress.back(), 1.0);

  // --require-colour drops the depth-only frame.
  bag::ConvertOptions strict;
  strict.require_colour = true;
  TumRgbdConverter conv2(dir, strict, "fr3", bag::FallbackCalibration::defaults());
  EXPECT_DOUBLE_EQ(conv2.camera().fx, 535.4);
  RecordingSink sink2(RecordingSink::ImuKind::kAccelerometerOnly);
  const bag::ConversionReport r2 = conv2.run(sink2);
  EXPECT_EQ(sink2.frames.size(), 4u);
  EXPECT_EQ(r2.depth_alone_dropped, 1u);
}

TEST(TumRgbd, UnknownCameraNeedsAnOption) {
  const std::string parent = test::makeTempDir("tum");
  const std::string dir = makeFolder(parent);
  const std::string renamed = parent + "/my_kinect_run";
  fs::rename(dir, renamed);
  EXPECT_THROW(
      TumRgbdConverter(renamed, bag::ConvertOptions(), "", bag::FallbackCalibration::defaults()),
      std::invalid_argument);
  bag::FallbackCalibration user = bag::FallbackCalibration::defaults();
  user.intrinsics_from_user = true;
  user.color.fx = 500.0;
  user.color_source = "my.ini [camera]";
  TumRgbdConverter conv(renamed, bag::ConvertOptions(), "", user);
  EXPECT_DOUBLE_EQ(conv.camera().fx, 500.0);
}

}  // namespace
}  // namespace rgbdi::convert
