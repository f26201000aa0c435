// Keyframe ORB features for loop closure: count bound, spread over the image, determinism,
// depth-backed 3-D points on synthetic frames with exact depth, no point at holes and edges.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>

#include "frontend/synthetic_scene.h"
#include "rgbdi/loop/loop_features.h"

using rgbdi::PinholeCamera;
using rgbdi::RgbdFrame;
using rgbdi::loop::LoopFeatureExtractor;
using rgbdi::loop::LoopFeatureOptions;
using rgbdi::mapping::DescriptorSet;

namespace {

/// Random rectangles with grey levels in [lo, hi] over `area` of a CV_32FC1 image.
void paintRectangles(cv::Mat& img, const cv::Rect& area, int count, float lo, float hi,
                     std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> grey(lo, hi);
  std::uniform_int_distribution<int> x(area.x, area.x + area.width - 1),
      y(area.y, area.y + area.height - 1), side(6, 40);
  for (int i = 0; i < count; ++i) {
    const cv::Rect r(x(rng), y(rng), side(rng), side(rng));
    img(r & area).setTo(grey(rng));
  }
}

RgbdFrame texturedFrame(const PinholeCamera& cam, std::uint64_t seed = 3) {
  const cv::Mat tex = rgbdi::test::randomRectangleTexture(cam.width, cam.height, seed, 900, 1.0);
  return rgbdi::test::colourFrame(rgbdi::test::toGrey8(tex), 0.0, 0, cam);
}

/// Sets a CV_16UC1 millimetre depth image from z(u, v) [m] (0 = hole).
template <typename DepthFn>
void setDepth(RgbdFrame& f, int width, int height, DepthFn z) {
  f.depth = cv::Mat(height, width, CV_16UC1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(std::lround(z(u, v) * 1000.0));
  f.depth_unit_m = 1e-3;
  f.depth_aligned_to_color = true;
  f.cam_depth = f.cam_color;
}

bool identical(const DescriptorSet& a, const DescriptorSet& b) {
  if (a.type != b.type || a.size() != b.size() || a.data != b.data ||
      a.keypoints_uv != b.keypoints_uv || a.keypoints_p_cam.size() != b.keypoints_p_cam.size())
    return false;
  return a.keypoints_p_cam.empty() ||
         std::memcmp(a.keypoints_p_cam.data(), b.keypoints_p_cam.data(),
                     a.keypoints_p_cam.size() * sizeof(Eigen::Vector3f)) == 0;
}

/// The pixel window sampleDepth checks for a keypoint (nearest pixel +- n, bilinear support).
cv::Rect checkedWindow(const Eigen::Vector2f& uv, int n) {
  const int u0 = static_cast<int>(std::floor(uv.x())), v0 = static_cast<int>(std::floor(uv.y()));
  const int uc = static_cast<int>(std::lround(uv.x())), vc = static_cast<int>(std::lround(uv.y()));
  const int umin = std::min(uc - n, u0), vmin = std::min(vc - n, v0);
  const int umax = std::max(uc + n, u0 + 1), vmax = std::max(vc + n, v0 + 1);
  return {umin, vmin, umax - umin + 1, vmax - vmin + 1};
}

/// The plane n . p = 2 in the camera frame, tilted against the image: its depth along the ray of
/// each pixel is z = 2 / (n . (x, y, 1)).
struct TiltedPlane {
  explicit TiltedPlane(const PinholeCamera& camera) : cam(camera) {}
  double z(double u, double v) const {
    const Eigen::Vector2d xn = cam.pixelToNormalized({u, v});
    return 2.0 / n.dot(Eigen::Vector3d(xn.x(), xn.y(), 1.0));
  }
  PinholeCamera cam;
  Eigen::Vector3d n{0.25, -0.15, 1.0};
};

}  // namespace

TEST(LoopFeatures, KeepsAtMostMaxKeypointsOfTypeOrb256InsideTheBorder) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  const RgbdFrame frame = texturedFrame(cam);
  LoopFeatureOptions o;
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, o);
  EXPECT_EQ(d.type, "ORB-256");
  EXPECT_EQ(d.bytes_per_descriptor, 32u);
  EXPECT_TRUE(d.consistent());
  EXPECT_TRUE(d.keypoints_p_cam.empty());  // the frame has no depth
  EXPECT_LE(d.size(), 400u);
  EXPECT_GE(d.size(), 360u);  // the texture has far more corners than that
  for (const Eigen::Vector2f& uv : d.keypoints_uv)
    EXPECT_TRUE(cam.inImage(uv.cast<double>(), o.border_px - 1.0)) << uv.transpose();

  o.max_keypoints = 50;
  const DescriptorSet few = rgbdi::loop::extractLoopFeatures(frame, cam, o);
  EXPECT_LE(few.size(), 50u);
  EXPECT_GE(few.size(), 45u);
}

TEST(LoopFeatures, SpreadsKeypointsOverTheImageWhenOneCornerIsRicher) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  // Weak texture everywhere, strong texture in the top-left quadrant only.
  cv::Mat img(cam.height, cam.width, CV_32FC1, cv::Scalar(128));
  paintRectangles(img, {0, 0, cam.width, cam.height}, 1200, 95.0f, 160.0f, 11);
  paintRectangles(img, {0, 0, cam.width / 2, cam.height / 2}, 500, 0.0f, 255.0f, 12);
  cv::GaussianBlur(img, img, cv::Size(0, 0), 1.0);
  const RgbdFrame frame = rgbdi::test::colourFrame(rgbdi::test::toGrey8(img), 0.0, 0, cam);

  const auto quadrantShares = [&](const DescriptorSet& d) {
    std::array<double, 4> share{0, 0, 0, 0};
    for (const Eigen::Vector2f& uv : d.keypoints_uv)
      share[(uv.x() >= cam.width / 2 ? 1 : 0) + (uv.y() >= cam.height / 2 ? 2 : 0)] +=
          1.0 / static_cast<double>(d.size());
    return share;
  };
  LoopFeatureOptions o;
  o.detect_candidates = 20000;    // every corner reaches the bucketing
  o.grid_cols = o.grid_rows = 1;  // no bucketing: the strong quadrant takes nearly everything
  const std::array<double, 4> plain =
      quadrantShares(rgbdi::loop::extractLoopFeatures(frame, cam, o));
  EXPECT_GT(plain[0], 0.8);

  o.grid_cols = 8;
  o.grid_rows = 6;
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, o);
  EXPECT_GE(d.size(), 360u);
  const std::array<double, 4> spread = quadrantShares(d);
  for (int q = 0; q < 4; ++q) {
    EXPECT_GT(spread[q], 0.18) << "quadrant " << q;
    EXPECT_LT(spread[q], 0.32) << "quadrant " << q;
  }
}

TEST(LoopFeatures, AreDeterministic) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 7);
  setDepth(frame, cam.width, cam.height, [](int u, int) { return u < 300 ? 1.2 : 2.5; });
  LoopFeatureExtractor a{LoopFeatureOptions()}, b{LoopFeatureOptions()};
  const DescriptorSet first = a.extract(frame, cam);
  ASSERT_GT(first.size(), 100u);
  EXPECT_TRUE(identical(first, a.extract(frame, cam)));  // same instance again
  EXPECT_TRUE(identical(first, b.extract(frame, cam)));  // another instance
  EXPECT_TRUE(identical(first, rgbdi::loop::extractLoopFeatures(frame, cam, LoopFeatureOptions())));
}

TEST(LoopFeatures, PointsEqualTheDepthOfATiltedPlaneAtTheKeypoint) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 5);
  const TiltedPlane plane(cam);
  setDepth(frame, cam.width, cam.height, [&](int u, int v) { return plane.z(u, v); });
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, LoopFeatureOptions());
  ASSERT_EQ(d.keypoints_p_cam.size(), d.size());
  ASSERT_GT(d.size(), 300u);
  for (std::size_t k = 0; k < d.size(); ++k) {
    ASSERT_TRUE(d.hasPoint(k)) << "keypoint " << k << " at " << d.keypoints_uv[k].transpose();
    const Eigen::Vector2d uv = d.keypoints_uv[k].cast<double>();
    const Eigen::Vector3d expected = cam.backProject(uv, plane.z(uv.x(), uv.y()));
    // Millimetre quantisation of the depth image and bilinear interpolation: < 1 mm.
    EXPECT_LT((d.keypoints_p_cam[k].cast<double>() - expected).norm(), 1e-3) << "keypoint " << k;
    EXPECT_NEAR(plane.n.dot(d.keypoints_p_cam[k].cast<double>()), 2.0, 1e-3);  // on the plane
  }
}

TEST(LoopFeatures, KeypointsMovedToTheStampTakeTheirDepthThere) {
  // Rolling shutter: to_stamp maps each keypoint to its pixel at the stamp (here 3 px left and
  // 2 px up); keypoints_uv and the points are taken there, where the global-shutter depth is.
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 5);
  const TiltedPlane plane(cam);
  setDepth(frame, cam.width, cam.height, [&](int u, int v) { return plane.z(u, v); });
  const Eigen::Vector2d shift(-3.0, -2.0);
  LoopFeatureExtractor plain(LoopFeatureOptions{}), moved(LoopFeatureOptions{});
  const DescriptorSet a = plain.extract(frame, cam);
  const DescriptorSet b =
      moved.extract(frame, cam, [&](const Eigen::Vector2d& uv) { return uv + shift; });
  ASSERT_EQ(a.size(), b.size());
  ASSERT_GT(b.size(), 300u);
  EXPECT_EQ(a.data, b.data);  // the same keypoints and descriptors
  for (std::size_t k = 0; k < b.size(); ++k) {
    const Eigen::Vector2d uv = a.keypoints_uv[k].cast<double>() + shift;
    EXPECT_LT((b.keypoints_uv[k].cast<double>() - uv).norm(), 1e-4) << "keypoint " << k;
    if (!b.hasPoint(k)) continue;
    const Eigen::Vector3d expected = cam.backProject(uv, plane.z(uv.x(), uv.y()));
    EXPECT_LT((b.keypoints_p_cam[k].cast<double>() - expected).norm(), 1e-3) << "keypoint " << k;
  }
}

TEST(LoopFeatures, HolesAndDepthEdgesGiveNoPoint) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 9);
  const cv::Rect hole(100, 120, 90, 70);
  const int edge_u = 330;  // z = 1.5 m left of it, 3 m from it on
  setDepth(frame, cam.width, cam.height, [&](int u, int v) {
    if (hole.contains(cv::Point(u, v))) return 0.0;
    return u < edge_u ? 1.5 : 3.0;
  });
  const LoopFeatureOptions o;
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, o);
  ASSERT_EQ(d.keypoints_p_cam.size(), d.size());
  int near_defect = 0, clean = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    const cv::Rect w = checkedWindow(d.keypoints_uv[k], o.depth_window_px);
    const bool on_hole = (w & hole).area() > 0;
    const bool on_edge = w.x < edge_u && w.x + w.width - 1 >= edge_u;
    if (on_hole || on_edge) {
      ++near_defect;
      EXPECT_FALSE(d.hasPoint(k)) << "keypoint " << k << " at " << d.keypoints_uv[k].transpose();
      EXPECT_TRUE(std::isnan(d.keypoints_p_cam[k].x()) && std::isnan(d.keypoints_p_cam[k].y()));
    } else {
      ++clean;
      ASSERT_TRUE(d.hasPoint(k)) << "keypoint " << k << " at " << d.keypoints_uv[k].transpose();
      EXPECT_NEAR(d.keypoints_p_cam[k].z(), d.keypoints_uv[k].x() < edge_u ? 1.5 : 3.0, 1e-6);
    }
  }
  EXPECT_GE(near_defect, 3);  // the case is exercised
  EXPECT_GE(clean, 200);
}

TEST(LoopFeatures, OutOfRangeDepthGivesNoPoint) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 4);
  setDepth(frame, cam.width, cam.height, [](int u, int) { return u < 320 ? 0.2 : 7.0; });
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, LoopFeatureOptions());
  ASSERT_GT(d.size(), 100u);
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_FALSE(d.hasPoint(k));
}

TEST(LoopFeatures, UnalignedDepthIsRegisteredToTheColourCamera) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame frame = texturedFrame(cam, 6);
  // A fronto-parallel wall at 2 m seen by a depth camera with other intrinsics, 5 cm to the side.
  PinholeCamera cam_d;
  cam_d.width = 640;
  cam_d.height = 480;
  cam_d.fx = cam_d.fy = 650.0;  // a narrower view than the colour camera's
  cam_d.cx = 319.5;
  cam_d.cy = 239.5;
  frame.cam_depth = cam_d;
  frame.depth = cv::Mat(cam_d.height, cam_d.width, CV_16UC1, cv::Scalar(2000));
  frame.depth_aligned_to_color = false;
  frame.T_color_depth.translation() = Eigen::Vector3d(0.05, 0.0, 0.0);
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(frame, cam, LoopFeatureOptions());
  ASSERT_EQ(d.keypoints_p_cam.size(), d.size());
  std::size_t with_point = 0, unseen = 0;
  for (std::size_t k = 0; k < d.size(); ++k) {
    Eigen::Vector2d uv_seen;
    cam_d.project(
        frame.T_color_depth.inverse() * cam.backProject(d.keypoints_uv[k].cast<double>(), 2.0),
        uv_seen);
    if (!cam_d.inImage(uv_seen, 4.0)) ++unseen;
    if (!d.hasPoint(k)) continue;
    ++with_point;
    EXPECT_NEAR(d.keypoints_p_cam[k].z(), 2.0, 1e-3);
    // Colour pixels the depth camera cannot see (its view is narrower) get no point.
    Eigen::Vector2d uv_d;
    ASSERT_TRUE(
        cam_d.project(frame.T_color_depth.inverse() * d.keypoints_p_cam[k].cast<double>(), uv_d));
    EXPECT_TRUE(cam_d.inImage(uv_d)) << uv_d.transpose();
  }
  EXPECT_GE(with_point + unseen, d.size() * 9 / 10);
  EXPECT_GT(unseen, 10u);  // the case is exercised
}

TEST(LoopFeatures, FramesWithoutColourGiveAnEmptySetAndBadSizesThrow) {
  const PinholeCamera cam = rgbdi::test::simpleCamera();
  RgbdFrame depth_only;
  depth_only.cam_color = cam;
  const DescriptorSet d = rgbdi::loop::extractLoopFeatures(depth_only, cam, LoopFeatureOptions());
  EXPECT_EQ(d.size(), 0u);
  EXPECT_EQ(d.type, "ORB-256");
  EXPECT_TRUE(d.consistent());
  RgbdFrame frame = texturedFrame(cam);
  PinholeCamera other = cam;
  other.width = 320;
  try {
    rgbdi::loop::extractLoopFeatures(frame, other, LoopFeatureOptions());
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic frame 0"), std::string::npos) << e.what();
  }
}
