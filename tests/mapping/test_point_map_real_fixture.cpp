// The point mapper on a real OpenNI2 RGB-D observation (depth not registered to colour): its
// grid points must agree with MRPT's own documented unprojection of the same depth pixels.
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CRawlog.h>

#include <iostream>
#include <vector>

#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/mapping/map_export.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "testing/fixtures.h"

using namespace rgbdi::mapping;

namespace {

mrpt::obs::CObservation3DRangeScan::Ptr loadObservation(const std::string& path) {
  mrpt::obs::CRawlog log;
  if (!log.loadFromRawLogFile(path)) throw std::runtime_error("cannot read " + path);
  for (std::size_t i = 0; i < log.size(); ++i)
    if (log.getType(i) == mrpt::obs::CRawlog::etObservation)
      if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(
              log.getAsObservation(i))) {
        o->load();
        return o;
      }
  throw std::runtime_error(path + ": no CObservation3DRangeScan");
}

/// Inverse of the radial distortion x_d = x_u (1 + k1 r^2 + k2 r^4) by Newton's method on the
/// radius (independent of the library's fixed-point undistortion).
Eigen::Vector2d undistortRadial(const Eigen::Vector2d& xd, double k1, double k2) {
  const double rd = xd.norm();
  if (rd == 0.0) return xd;
  double r = rd;
  for (int i = 0; i < 30; ++i) {
    const double r2 = r * r;
    r -= (r * (1 + k1 * r2 + k2 * r2 * r2) - rd) / (1 + 3 * k1 * r2 + 5 * k2 * r2 * r2);
  }
  return xd * (r / rd);
}

}  // namespace

TEST(PointMapRealFixture, OpenNi2GridPointsAgreeWithMrptsUnprojection) {
  const std::string path = rgbdi::test::fixturePath("real/openni2_single_rgbd.rawlog");
  RGBDI_REQUIRE_FIXTURE(path);
  const auto obs = loadObservation(path);
  const rgbdi::RgbdFrame frame = rgbdi::io::fromMrpt(*obs, path + " record 0");
  ASSERT_FALSE(frame.depth_aligned_to_color);

  const MappingOptions o;
  PointMap map(o);
  const std::vector<MapPoint> kept = map.insertKeyframe(frame, Eigen::Isometry3d::Identity());

  // MRPT's convention (CObservation3DRangeScan docs): depth frame x forward,
  // y = (cx - c) / fx * x, z = (cy - r) / fy * x, then into the colour optical frame through
  // relativePoseIntensityWRTDepth. That formula ignores the depth lens distortion (radial
  // k1 = -0.0047, k2 = -0.0044 here): `expected_raw` follows it literally (millimetres apart at
  // the image corners), `expected` applies it to the undistorted pixel (must agree exactly).
  const auto& cam = obs->cameraParams;
  ASSERT_EQ(cam.dist[2], 0.0);
  ASSERT_EQ(cam.dist[3], 0.0);
  ASSERT_EQ(cam.dist[4], 0.0);
  std::vector<Eigen::Vector3d> expected, expected_raw;
  for (int v = o.v_min_px; v <= o.v_max_px && v < frame.depth.rows; v += o.grid_step_px)
    for (int u = o.u_min_px; u <= o.u_max_px && u < frame.depth.cols; u += o.grid_step_px) {
      const std::uint16_t d = obs->rangeImage(v, u);
      const double x = d * obs->rangeUnits;
      if (d == 0 || !(x > o.depth_min_m && x < o.depth_max_m)) continue;
      const mrpt::math::TPoint3D p_depth(x, (cam.cx() - u) / cam.fx() * x,
                                         (cam.cy() - v) / cam.fy() * x);
      const mrpt::math::TPoint3D p =
          obs->relativePoseIntensityWRTDepth.inverseComposePoint(p_depth);
      expected_raw.emplace_back(p.x, p.y, p.z);
      const Eigen::Vector2d xn = undistortRadial(
          {(u - cam.cx()) / cam.fx(), (v - cam.cy()) / cam.fy()}, cam.dist[0], cam.dist[1]);
      const mrpt::math::TPoint3D q = obs->relativePoseIntensityWRTDepth.inverseComposePoint(
          mrpt::math::TPoint3D(x, -xn.x() * x, -xn.y() * x));
      expected.emplace_back(q.x, q.y, q.z);
    }
  ASSERT_GT(expected.size(), 2000u);  // the sensor sees 1.62-2.56 m almost everywhere
  EXPECT_EQ(map.stats().candidates, expected.size());
  // 10 px at ~525 px focal length and 1.6 m is 3 cm: a 2 cm leaf never receives 6 grid points.
  ASSERT_EQ(kept.size(), expected.size());
  double max_diff = 0.0, max_diff_raw = 0.0;
  std::size_t coloured = 0;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    max_diff = std::max(max_diff, (kept[i].p_cam.cast<double>() - expected[i]).norm());
    max_diff_raw = std::max(max_diff_raw, (kept[i].p_cam.cast<double>() - expected_raw[i]).norm());
    coloured += kept[i].rgb != kUncolouredRgb;
  }
  std::cout << kept.size() << " points, max difference to MRPT's unprojection "
            << max_diff_raw * 1e3 << " mm (distortion ignored), " << max_diff * 1e3
            << " mm (undistorted), " << coloured << " coloured\n";
  EXPECT_LT(max_diff_raw, 0.005);
  EXPECT_LT(max_diff, 1e-5);
  EXPECT_GT(coloured, kept.size() * 9 / 10);

  // The whole output chain works on real data.
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_real_map");
  writePly(dir + "/map.ply", map);
  writePointsMap(dir + "/map.pointsmap", map);
  OccupancyMap occupancy(o);
  occupancy.insert(frame, Eigen::Isometry3d::Identity());
  occupancy.write(dir + "/map.bt");
  EXPECT_GT(occupancy.leafCount(), 1000u);
}
