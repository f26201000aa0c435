// The rendered images must behave like real imagery for the front end: Shi-Tomasi corners
// tracked by pyramidal KLT between two consecutive frames land where the scene geometry says.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/renderer.h"
#include "rgbdi/sim/scene_presets.h"
#include "rgbdi/sim/sensor_noise.h"

namespace rgbdi::sim {
namespace {

Eigen::Isometry3d lookFrom(const Eigen::Vector3d& eye, double yaw, double pitch) {
  Eigen::Matrix3d R_body_cam;
  R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix() *
               R_body_cam;
  T.translation() = eye;
  return T;
}

struct TrackStats {
  int corners = 0, checked = 0, within_half_px = 0;
  double median_error = 0.0;
};

// Renders two noisy frames, tracks corners from the first to the second and compares with the
// motion predicted from the ideal depth of the first frame.
TrackStats trackBetween(const Scene& scene, const Eigen::Isometry3d& Ta,
                        const Eigen::Isometry3d& Tb, std::uint64_t seed) {
  const PinholeCamera cam = CameraOptions().camera;
  const Renderer renderer(scene, cam);
  cv::Mat rgb_a, depth_a, rgb_b, depth_b, grey_a, grey_b;
  renderer.render(Ta, rgb_a, depth_a);
  renderer.render(Tb, rgb_b, depth_b);
  std::mt19937_64 rng(seed);
  applyColorNoise(rgb_a, ColorNoiseOptions{}, rng);
  applyColorNoise(rgb_b, ColorNoiseOptions{}, rng);
  cv::cvtColor(rgb_a, grey_a, cv::COLOR_RGB2GRAY);
  cv::cvtColor(rgb_b, grey_b, cv::COLOR_RGB2GRAY);

  // Front-end settings of the reference implementation (SPEC section 2).
  std::vector<cv::Point2f> pa, pb;
  cv::goodFeaturesToTrack(grey_a, pa, 200, 0.01, 15);
  std::vector<unsigned char> status;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(grey_a, grey_b, pa, pb, status, err, cv::Size(21, 21), 3);

  TrackStats s;
  s.corners = static_cast<int>(pa.size());
  std::vector<double> errors;
  const Eigen::Isometry3d T_b_a = Tb.inverse() * Ta;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const int u = static_cast<int>(std::lround(pa[i].x)),
              v = static_cast<int>(std::lround(pa[i].y));
    if (u < 2 || v < 2 || u >= cam.width - 2 || v >= cam.height - 2) continue;
    // Corners on depth edges have no single true motion: keep locally planar ones.
    double lo = 1e9, hi = 0;
    for (int dv = -2; dv <= 2; ++dv)
      for (int du = -2; du <= 2; ++du) {
        const double z = depth_a.at<float>(v + dv, u + du);
        lo = std::min(lo, z);
        hi = std::max(hi, z);
      }
    if (lo <= 0.0 || hi - lo > 0.03 * lo) continue;
    // Depth at the sub-pixel corner: interpolate the locally smooth depth.
    cv::Mat patch;
    cv::getRectSubPix(depth_a, {1, 1}, pa[i], patch);
    const double z = patch.at<float>(0, 0);
    const Eigen::Vector3d p_b = T_b_a * cam.backProject({pa[i].x, pa[i].y}, z);
    Eigen::Vector2d uv_b;
    if (!cam.project(p_b, uv_b) || !cam.inImage(uv_b, 12)) continue;
    ++s.checked;
    const double e = status[i] ? std::hypot(pb[i].x - uv_b.x(), pb[i].y - uv_b.y()) : 1e9;
    errors.push_back(e);
    if (e < 0.5) ++s.within_half_px;
  }
  if (!errors.empty()) {
    std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
    s.median_error = errors[errors.size() / 2];
  }
  return s;
}

TEST(RenderTracking, KltFollowsTheTrueMotionBetweenFrames) {
  const Scene scene = makeFurnishedRoom(17);
  // Ground-robot motions over one 30 Hz frame: forward 3 cm with a 0.6 deg turn; a faster turn
  // (3 deg) while moving; a small pitch change on a bump.
  struct Motion {
    Eigen::Isometry3d a, b;
  };
  const Motion motions[] = {
      {lookFrom({0.0, 0.0, 0.4}, 0.3, 0.0),
       lookFrom({0.03 * std::cos(0.3), 0.03 * std::sin(0.3), 0.4}, 0.31, 0.0)},
      {lookFrom({0.5, -0.3, 0.4}, 2.0, 0.05), lookFrom({0.5, -0.28, 0.4}, 2.05, 0.05)},
      {lookFrom({-0.4, 0.6, 0.35}, -1.7, -0.05), lookFrom({-0.41, 0.58, 0.36}, -1.7, -0.035)}};
  for (std::size_t m = 0; m < 3; ++m) {
    const TrackStats s = trackBetween(scene, motions[m].a, motions[m].b, 100 + m);
    std::printf("motion %zu: %d corners, %d checked, median error %.3f px, %d within 0.5 px\n", m,
                s.corners, s.checked, s.median_error, s.within_half_px);
    EXPECT_GE(s.corners, 150) << "motion " << m;
    EXPECT_GE(s.checked, 60) << "motion " << m;
    EXPECT_LT(s.median_error, 0.15) << "motion " << m;
    EXPECT_GE(s.within_half_px, 0.9 * s.checked) << "motion " << m;
  }
}

}  // namespace
}  // namespace rgbdi::sim
