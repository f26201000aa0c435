// Rolling-shutter rendering: under a known yaw rate each colour row is shifted by the analytic
// amount of its row's rotation, depth stays the global-shutter image, equal poses give exactly
// the global-shutter image; the row timing of common/rolling_shutter.h on known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/renderer.h"

namespace rgbdi::sim {
namespace {

// Optical frame (x right, y down, z forward) looking horizontally along yaw from `eye`.
Eigen::Isometry3d lookFrom(const Eigen::Vector3d& eye, double yaw) {
  Eigen::Matrix3d R_body_cam;
  R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_body_cam;
  T.translation() = eye;
  return T;
}

// Camera turned about its own y axis (the world vertical for a level camera) by angle [rad].
Eigen::Isometry3d turned(const Eigen::Isometry3d& T, double angle) {
  Eigen::Isometry3d R = Eigen::Isometry3d::Identity();
  R.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T * R;
}

// Sub-pixel horizontal shift s with a(v, u) ~= b(v, u - s) over the columns [u0, u1): the
// minimum of the sum of squared differences, refined by a parabola.
double rowShift(const cv::Mat& a, const cv::Mat& b, int v, int u0, int u1, int max_shift) {
  std::vector<double> ssd;
  for (int s = -max_shift; s <= max_shift; ++s) {
    double e = 0.0;
    for (int u = u0; u < u1; ++u) {
      const double d = a.at<std::uint8_t>(v, u) - b.at<std::uint8_t>(v, u - s);
      e += d * d;
    }
    ssd.push_back(e);
  }
  std::size_t k = 1;
  for (std::size_t i = 1; i + 1 < ssd.size(); ++i)
    if (ssd[i] < ssd[k]) k = i;
  const double l = ssd[k - 1], c = ssd[k], r = ssd[k + 1];
  return static_cast<double>(k) - max_shift + 0.5 * (l - r) / (l - 2.0 * c + r);
}

cv::Mat grey(const cv::Mat& rgb) {
  cv::Mat g;
  cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
  return g;
}

TEST(RollingShutterTiming, RowTimesOfEachDirectionAndReference) {
  RollingShutter rs;
  rs.rows = 480;
  EXPECT_TRUE(rs.global());
  EXPECT_EQ(rs.rowTime(0.0), 0.0);
  rs.readout_s = 0.048;  // 0.1 ms per row
  EXPECT_DOUBLE_EQ(rs.referenceRow(), 239.5);
  EXPECT_NEAR(rs.rowTime(239.5), 0.0, 1e-15);
  EXPECT_NEAR(rs.rowTime(0.0), -0.02395, 1e-15);
  EXPECT_NEAR(rs.rowTime(479.0), 0.02395, 1e-15);
  rs.bottom_to_top = true;
  EXPECT_NEAR(rs.rowTime(0.0), 0.02395, 1e-15);
  rs.reference_middle = false;  // first row read: the bottom one
  EXPECT_DOUBLE_EQ(rs.referenceRow(), 479.0);
  EXPECT_NEAR(rs.rowTime(0.0), 0.0479, 1e-15);
  EXPECT_NEAR(rs.rowTime(479.0), 0.0, 1e-15);
  rs.bottom_to_top = false;
  EXPECT_DOUBLE_EQ(rs.referenceRow(), 0.0);
  EXPECT_NEAR(rs.rowTime(100.0), 0.01, 1e-15);
}

class RollingShutterRender : public ::testing::Test {
 protected:
  RollingShutterRender() : scene_(7) {
    scene_.addRoom({-3, -4, 0}, {6, 4, 3});
    scene_.build();
  }
  Scene scene_;
  PinholeCamera cam_ = CameraOptions().camera;
};

TEST_F(RollingShutterRender, KnownYawRateShiftsEachRowByItsRotation) {
  const Renderer renderer(scene_, cam_);
  RollingShutter rs;
  rs.readout_s = 0.033;
  rs.rows = cam_.height;
  const double yaw_rate = 1.0;  // [rad/s] about the camera's y axis
  const Eigen::Isometry3d T_ref = lookFrom({0.0, 0.2, 1.4}, 0.1);
  std::vector<Eigen::Isometry3d> rows;
  for (int v = 0; v < cam_.height; ++v) rows.push_back(turned(T_ref, yaw_rate * rs.rowTime(v)));
  cv::Mat rgb_rs, depth_rs, rgb_gs, depth_gs;
  renderer.renderRollingShutter(rows, T_ref, rgb_rs, depth_rs);
  renderer.render(T_ref, rgb_gs, depth_gs);
  // Depth is the global-shutter image at the reference pose, bit for bit.
  EXPECT_EQ(cv::norm(depth_rs, depth_gs, cv::NORM_INF), 0.0);
  const cv::Mat a = grey(rgb_rs), b = grey(rgb_gs);
  double largest = 0.0;
  for (int v : {20, 100, 200, 240, 300, 380, 460}) {
    // Analytic: the point seen through the centre column in the reference image, seen from the
    // row's turned camera.
    const Eigen::Vector3d ray = cam_.backProject({cam_.cx, v}, 1.0);
    const double angle = yaw_rate * rs.rowTime(v);
    Eigen::Vector2d uv;
    ASSERT_TRUE(
        cam_.project(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).inverse() * ray, uv));
    const double expected = uv.x() - cam_.cx;
    const double measured = rowShift(a, b, v, 240, 400, 20);
    // 0.25 px: the parabola through the SSD of integer shifts locks a little to whole pixels.
    EXPECT_NEAR(measured, expected, 0.25) << "row " << v;
    largest = std::max(largest, std::abs(expected));
  }
  // The D435i case of the issue: ~20 px from top to bottom at 1 rad/s, half each side.
  EXPECT_GT(largest, 9.0);
}

TEST_F(RollingShutterRender, EqualRowPosesGiveTheGlobalShutterImage) {
  const Renderer renderer(scene_, cam_);
  const Eigen::Isometry3d T = lookFrom({0.5, -0.3, 1.2}, -0.7);
  cv::Mat rgb_rs, depth_rs, rgb_gs, depth_gs;
  renderer.renderRollingShutter(std::vector<Eigen::Isometry3d>(cam_.height, T), T, rgb_rs,
                                depth_rs);
  renderer.render(T, rgb_gs, depth_gs);
  EXPECT_EQ(cv::norm(rgb_rs, rgb_gs, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(depth_rs, depth_gs, cv::NORM_INF), 0.0);
}

TEST_F(RollingShutterRender, RefusesAPoseCountOtherThanTheRows) {
  const Renderer renderer(scene_, cam_);
  cv::Mat rgb, depth;
  const Eigen::Isometry3d T = lookFrom({0, 0, 1}, 0.0);
  EXPECT_THROW(renderer.renderRollingShutter(std::vector<Eigen::Isometry3d>(10, T), T, rgb, depth),
               std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
