// BagConverter on the real RealSense SDK recording (realsense-viewer layout, lz4 chunks, written by
// Intel's code, not ours): facts from ../shared/data/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "rgbdi/bag/bag_converter.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"

namespace rgbdi::bag {
namespace {

using test::RecordingSink;

std::string fixture() {
  return test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
}

TEST(BagConvertRealSense, LayoutAndCalibrationFromTheRecording) {
  RGBDI_REQUIRE_FIXTURE(fixture());
  BagConverter conv(fixture(), ConvertOptions(), BagInputOptions(),
                    FallbackCalibration::defaults());
  const BagLayout& l = conv.layout();
  EXPECT_EQ(l.kind, BagLayoutKind::RealSense);
  EXPECT_EQ(l.color, "/device_0/sensor_1/Color_0/image/data");
  EXPECT_EQ(l.depth, "/device_0/sensor_0/Depth_0/image/data");
  EXPECT_EQ(l.color_info, "/device_0/sensor_1/Color_0/info/camera_info");
  EXPECT_EQ(l.depth_info, "/device_0/sensor_0/Depth_0/info/camera_info");
  EXPECT_EQ(l.depth_units, "/device_0/sensor_0/option/Depth Units/value");
  EXPECT_EQ(l.color_tf, "/device_0/sensor_1/Color_0/tf/0");
  EXPECT_EQ(l.depth_tf, "/device_0/sensor_0/Depth_0/tf/0");
  EXPECT_TRUE(l.imu.empty());
  EXPECT_TRUE(l.accel.empty());
  EXPECT_FALSE(l.depth_aligned);

  EXPECT_NEAR(conv.depthCamera().fx, 390.43, 0.005);
  EXPECT_NEAR(conv.depthCamera().cx, 331.39, 0.005);
  EXPECT_EQ(conv.depthCamera().width, 640);
  EXPECT_NEAR(conv.colorCamera().fx, 613.20, 0.005);
  EXPECT_NEAR(conv.colorCamera().cx, 319.94, 0.005);
  EXPECT_DOUBLE_EQ(conv.depthUnit(), 0.001);
  // The SDK's extrinsic from depth to colour on this recording (rs2_get_extrinsics(depth ->
  // color) in librealsense 2.56.5 playback): p_color = R p_depth + t, t = (+0.014311, 0.000602,
  // 0.000611) m, 0.947 deg. The rotation's sign is that of rs2_extrinsics' column-major matrix
  // (rotation[6] = R(0,2) = +0.01293 from the recording's quaternion; a transposed reading
  // would give -0.01293).
  const Eigen::Isometry3d& T_color_depth = conv.T_color_depth();
  EXPECT_NEAR(T_color_depth.translation().x(), 0.014311, 1e-6);
  EXPECT_NEAR(T_color_depth.translation().y(), 0.000602, 1e-6);
  EXPECT_NEAR(T_color_depth.translation().z(), 0.000611, 1e-6);
  EXPECT_NEAR(Eigen::AngleAxisd(T_color_depth.rotation()).angle() * 180.0 / M_PI, 0.947, 5e-4);
  EXPECT_NEAR(T_color_depth.linear()(0, 2), 0.012926, 1e-6);
  EXPECT_NEAR(T_color_depth.linear()(0, 1), -0.010310, 1e-6);
  // The geometry of a D435: the colour camera sits beside the left imager (the depth origin),
  // about 15 mm on the side away from the right imager (depth x < 0).
  const Eigen::Vector3d color_in_depth = T_color_depth.inverse().translation();
  EXPECT_LT(color_in_depth.x(), -0.013);
  EXPECT_GT(color_in_depth.x(), -0.016);
  // No IMU in the recording: the sensor pose is the configured extrinsic.
  EXPECT_TRUE(conv.T_body_cam().isApprox(FallbackCalibration::defaults().T_body_cam));
}

/// Mean distance [px] (each capped at 10 px) from the depth discontinuities of `f`, moved into
/// the colour image with T_color_depth, to the nearest colour edge (Canny); `n` = discontinuities.
double depthEdgeToColourEdgePx(const RgbdFrame& f, const Eigen::Isometry3d& T_color_depth, int* n) {
  cv::Mat gray, edges, dist;
  cv::cvtColor(f.rgb, gray, cv::COLOR_RGB2GRAY);
  cv::Canny(gray, edges, 50, 150);
  cv::distanceTransform(255 - edges, dist, cv::DIST_L2, 3);
  const PinholeCamera &cd = f.cam_depth, &cc = f.cam_color;
  const auto z = [&](int u, int v) { return f.depth.at<std::uint16_t>(v, u) * f.depth_unit_m; };
  double sum = 0.0;
  *n = 0;
  for (int v = 0; v < f.depth.rows; ++v)
    for (int u = 0; u < f.depth.cols; ++u) {
      const double z0 = z(u, v);
      if (z0 < 0.2 || z0 > 5.0) continue;
      for (const auto& [du, dv] : {std::pair<int, int>{1, 0}, {0, 1}}) {
        // The next valid pixel right / below (occlusion boundaries have holes), at most 7 away.
        int k = 1;
        while (k < 8 && u + du * k < f.depth.cols && v + dv * k < f.depth.rows &&
               z(u + du * k, v + dv * k) <= 0.0)
          ++k;
        if (u + du * k >= f.depth.cols || v + dv * k >= f.depth.rows) continue;
        const double z1 = z(u + du * k, v + dv * k);
        if (z1 < 0.2 || z1 > 5.0 || std::abs(z1 - z0) < 0.15) continue;
        // The foreground side of the discontinuity, where the colour image has its edge.
        const int uf = z0 < z1 ? u : u + du * k, vf = z0 < z1 ? v : v + dv * k;
        const double zf = std::min(z0, z1);
        const Eigen::Vector3d p_depth((uf - cd.cx) / cd.fx * zf, (vf - cd.cy) / cd.fy * zf, zf);
        const Eigen::Vector3d p_color = T_color_depth * p_depth;
        const int uc = static_cast<int>(std::lround(cc.fx * p_color.x() / p_color.z() + cc.cx));
        const int vc = static_cast<int>(std::lround(cc.fy * p_color.y() / p_color.z() + cc.cy));
        if (uc < 0 || vc < 0 || uc >= cc.width || vc >= cc.height) continue;
        sum += std::min(dist.at<float>(vc, uc), 10.0f);
        ++*n;
      }
    }
  return *n ? sum / *n : 0.0;
}

TEST(BagConvertRealSense, TheReadExtrinsicRegistersDepthEdgesOntoColourEdges) {
  // Independent of librealsense: the recording's own images. Its colour image and first depth
  // image (0.1 s apart) paired; depth discontinuities moved into the colour
  // image with the extrinsic as read land on colour edges (measured 2.6 px mean, 55
  // discontinuities), with its inverse (the reading before 2026-12-03) 9.0 px, with none 7.7 px.
  RGBDI_REQUIRE_FIXTURE(fixture());
  ConvertOptions o;
  o.pair_tolerance_s = 0.15;
  BagConverter conv(fixture(), o, BagInputOptions(), FallbackCalibration::defaults());
  RecordingSink sink;
  conv.run(sink);
  ASSERT_FALSE(sink.frames.empty());
  const RgbdFrame& f = sink.frames[0];
  ASSERT_TRUE(f.hasColor());
  int n_read = 0, n_inverse = 0, n_none = 0;
  const double read = depthEdgeToColourEdgePx(f, conv.T_color_depth(), &n_read);
  const double inverse = depthEdgeToColourEdgePx(f, conv.T_color_depth().inverse(), &n_inverse);
  const double none = depthEdgeToColourEdgePx(f, Eigen::Isometry3d::Identity(), &n_none);
  EXPECT_GT(n_read, 40);
  EXPECT_LT(read, 3.0) << "inverse " << inverse << " px, identity " << none << " px";
  EXPECT_LT(read, 0.5 * inverse);
  EXPECT_LT(read, 0.5 * none);
}

TEST(BagConvertRealSense, TwoDepthOnlyFramesAndOneUnpairedColourFrame) {
  RGBDI_REQUIRE_FIXTURE(fixture());
  BagConverter conv(fixture(), ConvertOptions(), BagInputOptions(),
                    FallbackCalibration::defaults());
  RecordingSink sink;
  std::vector<double> progress;
  const ConversionReport r = conv.run(sink, [&](double f) { progress.push_back(f); });
  EXPECT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(sink.frames.size(), 2u);
  EXPECT_TRUE(sink.imus.empty());
  EXPECT_TRUE(sink.poses.empty());
  EXPECT_NEAR(sink.frames[0].t, 360.8151, 5e-5);
  EXPECT_NEAR(sink.frames[1].t, 360.9818, 5e-5);
  for (const RgbdFrame& f : sink.frames) {
    EXPECT_FALSE(f.hasColor());
    ASSERT_TRUE(f.hasDepth());
    EXPECT_EQ(f.depth.type(), CV_16UC1);
    EXPECT_EQ(f.depth.cols, 640);
    EXPECT_EQ(f.depth.rows, 480);
    EXPECT_DOUBLE_EQ(f.depth_unit_m, 0.001);
    EXPECT_FALSE(f.depth_aligned_to_color);
    EXPECT_NEAR(f.cam_depth.fx, 390.43, 0.005);
    EXPECT_NEAR(f.cam_color.fx, 613.20, 0.005);
    EXPECT_TRUE(f.T_color_depth.isApprox(conv.T_color_depth()));
    // A real scene: a good share of valid depth with a plausible median (0.3 - 10 m).
    std::vector<std::uint16_t> valid;
    for (int r2 = 0; r2 < f.depth.rows; r2 += 4)
      for (int c = 0; c < f.depth.cols; c += 4)
        if (const std::uint16_t v = f.depth.at<std::uint16_t>(r2, c)) valid.push_back(v);
    ASSERT_GT(valid.size(), 640u * 480u / 16u / 4u);
    std::nth_element(valid.begin(), valid.begin() + static_cast<long>(valid.size() / 2),
                     valid.end());
    const double median_m = valid[valid.size() / 2] * f.depth_unit_m;
    EXPECT_GT(median_m, 0.3);
    EXPECT_LT(median_m, 10.0);
  }
  EXPECT_EQ(r.color_images, 1u);
  EXPECT_EQ(r.depth_images, 2u);
  EXPECT_EQ(r.pairing.pairs, 0u);
  EXPECT_EQ(r.pairing.color_alone, 1u);
  EXPECT_EQ(r.pairing.depth_alone, 2u);
  const std::string text = r.text();
  EXPECT_NE(text.find("1 colour image(s) without a depth image within 0.020 s"), std::string::npos)
      << text;
  EXPECT_NE(text.find("no IMU topic (the recording has no Accel/Gyro streams)"), std::string::npos)
      << text;
  ASSERT_FALSE(progress.empty());
  EXPECT_DOUBLE_EQ(progress.back(), 1.0);
  for (std::size_t i = 1; i < progress.size(); ++i) EXPECT_GE(progress[i], progress[i - 1]);
}

TEST(BagConvertRealSense, ToleranceWideEnoughPairsTheColourFrame) {
  RGBDI_REQUIRE_FIXTURE(fixture());
  ConvertOptions o;
  o.pair_tolerance_s = 0.15;  // colour 360.7135 is 0.1016 s before the first depth image
  BagConverter conv(fixture(), o, BagInputOptions(), FallbackCalibration::defaults());
  RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  ASSERT_EQ(sink.frames.size(), 2u);
  EXPECT_TRUE(sink.frames[0].hasColor());
  EXPECT_NEAR(sink.frames[0].t, 360.7135, 5e-5);  // a pair takes the colour stamp
  EXPECT_EQ(sink.frames[0].rgb.type(), CV_8UC3);
  EXPECT_FALSE(sink.frames[1].hasColor());
  EXPECT_EQ(r.pairing.pairs, 1u);

  o.require_colour = true;
  BagConverter strict(fixture(), o, BagInputOptions(), FallbackCalibration::defaults());
  RecordingSink sink2;
  const ConversionReport r2 = strict.run(sink2);
  ASSERT_EQ(sink2.frames.size(), 1u);
  EXPECT_EQ(r2.depth_alone_dropped, 1u);
}

TEST(BagConvertRealSense, MissingTopicListsTheTopicsThatExist) {
  RGBDI_REQUIRE_FIXTURE(fixture());
  BagInputOptions in;
  in.topics.color = "/camera/color/image_raw";
  try {
    BagConverter conv(fixture(), ConvertOptions(), in, FallbackCalibration::defaults());
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("colour topic '/camera/color/image_raw' is not in the bag"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("/device_0/sensor_0/Depth_0/image/data"), std::string::npos) << what;
    EXPECT_NE(what.find("sensor_msgs/Image"), std::string::npos) << what;
  }
  in.topics.color = "/device_0/sensor_0/Depth_0/info/camera_info";
  try {
    BagConverter conv(fixture(), ConvertOptions(), in, FallbackCalibration::defaults());
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    EXPECT_NE(
        std::string(e.what()).find("has type sensor_msgs/CameraInfo, expected sensor_msgs/Image or "
                                   "sensor_msgs/CompressedImage"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::bag

namespace rgbdi::bag {
namespace {

TEST(BagConvertRealSense, TruncatedRecordingIsReportedAsTruncated) {
  RGBDI_REQUIRE_FIXTURE(fixture());
  const std::string dir = test::makeTempDir("rgbdi_rs_cut");
  const std::string cut = dir + "/cut.bag";
  std::filesystem::copy_file(fixture(), cut);
  std::filesystem::permissions(
      cut, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
  std::filesystem::resize_file(cut, 20000);  // the header and the start of the first chunk
  try {
    BagConverter conv(cut, ConvertOptions(), BagInputOptions(), FallbackCalibration::defaults());
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(cut + ": damaged bag: the bag index cannot be read", 0), 0u) << what;
    EXPECT_NE(what.find("the file is truncated"), std::string::npos) << what;
    EXPECT_NE(what.find("in the readable part: no colour or depth image topic found"),
              std::string::npos)
        << what;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rgbdi::bag
