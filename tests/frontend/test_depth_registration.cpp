// Depth registration: a plane + box scene rendered into a D435-like depth camera and colour camera
// (different intrinsics, colour distortion, offset and slight rotation), registered depth compared
// with the depth rendered directly in the colour camera.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "rgbdi/frontend/depth_registration.h"
#include "synthetic_scene.h"

using rgbdi::PinholeCamera;
using rgbdi::RgbdFrame;
using rgbdi::frontend::FrontendOptions;
using rgbdi::frontend::registerDepthToColor;
using namespace rgbdi::test;

namespace {

constexpr double kDepthUnit = 1e-4;  // 0.1 mm units keep quantisation far below the 1 mm check

struct RigScene {
  PinholeCamera cam_color, cam_depth;
  Eigen::Isometry3d T_color_depth = Eigen::Isometry3d::Identity();
  Scene scene;
  int box_front = -1;  ///< surface index of the box face towards the cameras
  RenderOutput color_truth, depth_view;
  RgbdFrame frame;
};

RigScene makeRig() {
  RigScene r;
  // Colour camera: D435-like, with mild distortion so both projection paths are exercised.
  r.cam_color.width = 640;
  r.cam_color.height = 480;
  r.cam_color.fx = 613.2;
  r.cam_color.fy = 612.9;
  r.cam_color.cx = 319.9;
  r.cam_color.cy = 243.1;
  r.cam_color.dist = {0.06, -0.12, 0.0005, -0.0003, 0.0};
  // Depth camera: wider field of view, so colour is magnified about 1.57x (cracks appear).
  r.cam_depth.width = 640;
  r.cam_depth.height = 480;
  r.cam_depth.fx = r.cam_depth.fy = 390.4;
  r.cam_depth.cx = 331.4;
  r.cam_depth.cy = 237.8;
  r.cam_depth.dist = {0.01, -0.005, 0.0, 0.0, 0.0};
  r.T_color_depth.linear() = (Eigen::AngleAxisd(0.4 * M_PI / 180, Eigen::Vector3d::UnitY()) *
                              Eigen::AngleAxisd(-0.25 * M_PI / 180, Eigen::Vector3d::UnitX()))
                                 .toRotationMatrix();
  r.T_color_depth.translation() = Eigen::Vector3d(-0.0143, -0.0006, -0.0006);

  // World = colour camera frame. Background: a plane about 2.2 m away turned 15 deg about y.
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(15.0 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d centre(0, 0, 2.2);
  const Eigen::Vector3d ex = tilt * Eigen::Vector3d(6, 0, 0), ey = tilt * Eigen::Vector3d(0, 6, 0);
  r.scene.rects.push_back({centre - 0.5 * ex - 0.5 * ey, ex, ey, -1});
  // A box in front of it: its front face at z = 1.1 covers a good part of the image.
  r.box_front = r.scene.addBox({-0.25, -0.15, 1.1}, {0.15, 0.2, 1.5}, -1);

  r.color_truth = render(r.scene, r.cam_color, Eigen::Isometry3d::Identity());
  r.depth_view = render(r.scene, r.cam_depth, r.T_color_depth);

  RgbdFrame& f = r.frame;
  f.t = 1.0;
  f.index = 7;
  f.source_label = "synthetic rig frame";
  f.rgb = cv::Mat(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
  f.cam_color = r.cam_color;
  f.cam_depth = r.cam_depth;
  f.T_color_depth = r.T_color_depth;
  f.depth_aligned_to_color = false;
  f.depth_unit_m = kDepthUnit;
  f.depth = cv::Mat(480, 640, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const double z = r.depth_view.depth.at<double>(v, u);
      if (z > 0)
        f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(z / kDepthUnit));
    }
  return r;
}

/// True when the depth camera sees the surface point shown at colour pixel (u, v).
bool seenByDepthCamera(const RigScene& r, int u, int v) {
  const double z = r.color_truth.depth.at<double>(v, u);
  const Eigen::Vector3d p_color = r.cam_color.backProject({double(u), double(v)}, z);
  const Eigen::Vector3d p_depth = r.T_color_depth.inverse() * p_color;
  Eigen::Vector2d uv;
  if (!r.cam_depth.project(p_depth, uv) || !r.cam_depth.inImage(uv, 1.0)) return false;
  // Every depth pixel around the projection must see this same point (not an occluder).
  for (int dv = 0; dv <= 1; ++dv)
    for (int du = 0; du <= 1; ++du) {
      const int x = static_cast<int>(std::floor(uv.x())) + du,
                y = static_cast<int>(std::floor(uv.y())) + dv;
      if (std::abs(r.depth_view.depth.at<double>(y, x) - p_depth.z()) > 0.01) return false;
    }
  return true;
}

}  // namespace

TEST(DepthRegistration, MatchesColourCameraDepthAndKeepsTheNearerSurface) {
  const RigScene r = makeRig();
  const cv::Mat reg = registerDepthToColor(r.frame);
  ASSERT_EQ(reg.type(), CV_32FC1);
  ASSERT_EQ(reg.size(), cv::Size(640, 480));

  int compared = 0, box_pixels = 0, visible = 0, covered = 0, empty_box_pixels = 0;
  double worst_inner = 0.0, worst_near_edge = 0.0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      // Pixels whose neighbourhood crosses a depth edge are ambiguous for any forward mapping.
      if (!uniformSurface(r.color_truth.surface, u, v, 1)) continue;
      const double truth = r.color_truth.depth.at<double>(v, u);
      const double got = reg.at<float>(v, u);
      const bool on_box = r.color_truth.surface.at<int>(v, u) == r.box_front;
      if (seenByDepthCamera(r, u, v)) {
        ++visible;
        if (got > 0) ++covered;
      }
      if (got <= 0) {
        if (on_box) ++empty_box_pixels;
        continue;
      }
      ++compared;
      // Away from edges (the 5x5 window sampleDepth checks) values come from the nearest point or
      // a symmetric interpolation; right next to an edge a crack may be closed from a point up
      // to one pixel away.
      const double err = std::abs(got - truth);
      if (uniformSurface(r.color_truth.surface, u, v, 2))
        worst_inner = std::max(worst_inner, err);
      else
        worst_near_edge = std::max(worst_near_edge, err);
      if (on_box) {
        ++box_pixels;
        // z-buffer: background (about 2.2 m) must never show through the box (1.1 m).
        ASSERT_NEAR(got, truth, 1e-3) << "box pixel " << u << "," << v;
      }
    }
  std::cout << "registration: " << compared << " pixels compared, worst error " << worst_inner * 1e3
            << " mm (" << worst_near_edge * 1e3 << " mm within 2 px of an edge), coverage "
            << covered << "/" << visible << ", box pixels " << box_pixels << "\n";
  EXPECT_LT(worst_inner, 1e-3) << "largest |registered - true| depth [m]";
  // Steepest background slope in this scene: 1.3 mm per colour pixel.
  EXPECT_LT(worst_near_edge, 1.5e-3);
  EXPECT_GT(compared, 200000);
  EXPECT_GT(box_pixels, 30000);
  // Magnification leaves regular 1-pixel cracks: crack filling must close practically all of them.
  EXPECT_GT(static_cast<double>(covered) / visible, 0.995) << covered << " of " << visible;
  EXPECT_LT(empty_box_pixels, 50);
}

TEST(DepthRegistration, NothingIsInventedWhereTheDepthCameraIsOccluded) {
  const RigScene r = makeRig();
  const cv::Mat reg = registerDepthToColor(r.frame);
  // Background pixels next to the box that the depth camera cannot see (it sits 14 mm to the
  // left) must stay empty: filling across the box edge would give them the box's depth.
  int occluded = 0, filled_wrongly = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      if (!uniformSurface(r.color_truth.surface, u, v, 1) || seenByDepthCamera(r, u, v)) continue;
      if (r.color_truth.surface.at<int>(v, u) == r.box_front) continue;
      ++occluded;
      const float got = reg.at<float>(v, u);
      if (got > 0 && std::abs(got - r.color_truth.depth.at<double>(v, u)) > 0.01) ++filled_wrongly;
    }
  std::cout << "disoccluded pixels: " << occluded << ", wrongly filled: " << filled_wrongly << "\n";
  EXPECT_GT(occluded, 100);  // the scene does have a disocclusion band
  EXPECT_EQ(filled_wrongly, 0);
}

TEST(DepthRegistration, RegisteringAroundPointsGivesTheSameValuesThere) {
  const RigScene r = makeRig();
  const cv::Mat full = registerDepthToColor(r.frame);
  // Points all over the image, including on the box edges, the borders and the corners.
  std::vector<Eigen::Vector2d> centres;
  for (int v = 0; v < 480; v += 37)
    for (int u = 0; u < 640; u += 29) centres.emplace_back(u + 0.3, v - 0.4);
  centres.emplace_back(0.0, 0.0);
  centres.emplace_back(639.0, 479.0);
  const int radius = 3;
  rgbdi::frontend::DepthRegistrar registrar;
  cv::Mat sparse;
  registrar.registerDepthAround(r.frame, r.cam_color, centres, radius, sparse);
  ASSERT_EQ(sparse.type(), CV_32FC1);
  ASSERT_EQ(sparse.size(), full.size());
  cv::Mat inside(480, 640, CV_8UC1, cv::Scalar(0));
  for (const Eigen::Vector2d& c : centres) {
    const cv::Rect w(static_cast<int>(std::lround(c.x())) - radius,
                     static_cast<int>(std::lround(c.y())) - radius, 2 * radius + 1, 2 * radius + 1);
    inside(w & cv::Rect(0, 0, 640, 480)).setTo(255);
  }
  int compared = 0, with_depth = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      if (!inside.at<std::uint8_t>(v, u)) {
        ASSERT_EQ(sparse.at<float>(v, u), 0.0f) << u << "," << v;
        continue;
      }
      ++compared;
      with_depth += full.at<float>(v, u) > 0 ? 1 : 0;
      ASSERT_EQ(sparse.at<float>(v, u), full.at<float>(v, u)) << u << "," << v;  // bit-identical
    }
  EXPECT_GT(compared, 13000);
  EXPECT_GT(with_depth, 12500);

  // The same registrar then serves a full registration unchanged (its buffers are reset).
  EXPECT_EQ(cv::norm(registrar.registerDepth(r.frame, r.cam_color), full, cv::NORM_INF), 0.0);
  // Aligned depth: the windows are plain unit conversions.
  RgbdFrame aligned = r.frame;
  aligned.depth_aligned_to_color = true;
  registrar.registerDepthAround(aligned, r.cam_color, {Eigen::Vector2d(100.2, 50.7)}, 2, sparse);
  EXPECT_FLOAT_EQ(sparse.at<float>(51, 100),
                  static_cast<float>(r.frame.depth.at<std::uint16_t>(51, 100) * kDepthUnit));
  EXPECT_EQ(sparse.at<float>(48, 100), 0.0f);
  EXPECT_EQ(cv::countNonZero(sparse), cv::countNonZero(r.frame.depth(cv::Rect(98, 49, 5, 5))));
}

TEST(DepthRegistration, OverlappingWindowsInTwoCallsGiveTheFullRegistrationsValues) {
  // Windows closer than their size (their depth regions overlap, and are projected once) in a
  // first call and more in a second call, also overlapping the first ones.
  const RigScene r = makeRig();
  const cv::Mat full = registerDepthToColor(r.frame);
  std::vector<Eigen::Vector2d> first, second;
  for (int v = 100; v < 380; v += 6)
    for (int u = 150; u < 500; u += 7) (((u + v) / 7) % 2 ? first : second).emplace_back(u, v);
  const int radius = 5;
  rgbdi::frontend::DepthRegistrar registrar;
  cv::Mat sparse;
  // A frame registered before must leave nothing behind (what it projected is not this frame's).
  registrar.registerDepthAround(r.frame, r.cam_color, second, radius, sparse);
  registrar.registerDepthAround(r.frame, r.cam_color, first, radius, sparse);
  registrar.registerMoreDepthAround(r.frame, r.cam_color, second, radius, sparse);
  int compared = 0;
  // The windows tile the grid's area without gaps (spacing below 2 radius + 1).
  for (int v = 100 - radius; v <= 376 + radius; ++v)
    for (int u = 150 - radius; u <= 493 + radius; ++u) {
      ASSERT_EQ(sparse.at<float>(v, u), full.at<float>(v, u)) << u << "," << v;
      compared += full.at<float>(v, u) > 0 ? 1 : 0;
    }
  EXPECT_GT(compared, 100000);
}

TEST(DepthRegistration, AlignedDepthIsOnlyConvertedToMetres) {
  RgbdFrame f;
  f.depth_aligned_to_color = true;
  f.cam_color = simpleCamera();
  f.depth_unit_m = 1e-3;
  f.depth = cv::Mat(480, 640, CV_16UC1, cv::Scalar(0));
  f.depth.at<std::uint16_t>(10, 20) = 1234;
  f.depth.at<std::uint16_t>(479, 639) = 65535;
  const cv::Mat reg = registerDepthToColor(f);
  ASSERT_EQ(reg.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(reg.at<float>(10, 20), 1.234f);
  EXPECT_FLOAT_EQ(reg.at<float>(479, 639), 65.535f);
  EXPECT_EQ(cv::countNonZero(reg), 2);
}

TEST(DepthRegistration, IdenticalCamerasReproduceTheDepthAndInterpolateAOnePixelHole) {
  RgbdFrame f;
  f.depth_aligned_to_color = false;  // forces the reprojection path
  f.cam_color = f.cam_depth = simpleCamera();
  f.depth_unit_m = 1e-3;
  f.depth = cv::Mat(480, 640, CV_16UC1);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
      f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(1000 + 2 * u + v);
  f.depth.at<std::uint16_t>(100, 101) = 0;  // a one-pixel hole
  const cv::Mat reg = registerDepthToColor(f);
  double worst = 0.0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
      worst = std::max(worst, std::abs(reg.at<float>(v, u) - (1000 + 2 * u + v) * 1e-3));
  // Everything, including the hole (mean of two opposite neighbours of a linear ramp), is exact
  // up to float precision.
  EXPECT_LT(worst, 1e-6);
}

TEST(DepthRegistration, BadInputNamesTheFrame) {
  RigScene r = makeRig();
  auto expectMessage = [](const RgbdFrame& f, const std::string& part) {
    try {
      registerDepthToColor(f);
      FAIL() << "expected std::invalid_argument containing " << part;
    } catch (const std::invalid_argument& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("synthetic rig frame"), std::string::npos) << msg;
      EXPECT_NE(msg.find(part), std::string::npos) << msg;
    }
  };
  RgbdFrame wrong_type = r.frame;
  r.frame.depth.convertTo(wrong_type.depth, CV_32F);
  expectMessage(wrong_type, "CV_16UC1");
  RgbdFrame wrong_size = r.frame;
  wrong_size.depth = r.frame.depth(cv::Rect(0, 0, 320, 240)).clone();
  expectMessage(wrong_size, "320x240");
  RgbdFrame no_intrinsics = r.frame;
  no_intrinsics.cam_depth = PinholeCamera();
  expectMessage(no_intrinsics, "depth intrinsics");
  RgbdFrame aligned_wrong_size = wrong_size;
  aligned_wrong_size.depth_aligned_to_color = true;
  expectMessage(aligned_wrong_size, "320x240");
  RgbdFrame bad_unit = r.frame;
  bad_unit.depth_unit_m = 0.0;
  expectMessage(bad_unit, "depth unit");
  RgbdFrame no_depth = r.frame;
  no_depth.depth = cv::Mat();
  expectMessage(no_depth, "no depth");
}
