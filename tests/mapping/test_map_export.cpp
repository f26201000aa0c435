// Map and scene files, each re-read with the library that consumes it: an own PLY reader,
// MRPT deserialisation (points map, 3-D scene, simple map) and cv::imread (trajectory plot).
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CColouredPointsMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/opengl/CCamera.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/serialization/CArchive.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/mapping/map_export.h"
#include "rgbdi/mapping/trajectory_plot.h"
#include "synthetic_frames.h"
#include "testing/fixtures.h"

using namespace rgbdi::mapping;
using rgbdi::StampedPose;
using rgbdi::Trajectory;
using rgbdi::mapping::test::planeFrame;

namespace {

/// Minimal reader of the PLY subset the writer promises (binary little-endian, float x y z,
/// uchar red green blue); any deviation from that header fails the test.
std::vector<WorldPoint> readPly(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  EXPECT_TRUE(is.good()) << path;
  std::string line;
  std::vector<std::string> header;
  std::size_t count = 0;
  while (std::getline(is, line) && line != "end_header") {
    header.push_back(line);
    if (line.rfind("element vertex ", 0) == 0) count = std::stoul(line.substr(15));
  }
  const std::vector<std::string> expected_props = {"property float x",     "property float y",
                                                   "property float z",     "property uchar red",
                                                   "property uchar green", "property uchar blue"};
  EXPECT_EQ(header.at(0), "ply");
  EXPECT_EQ(header.at(1), "format binary_little_endian 1.0");
  std::vector<std::string> props;
  for (const std::string& h : header)
    if (h.rfind("property", 0) == 0) props.push_back(h);
  EXPECT_EQ(props, expected_props);
  std::vector<char> body((std::istreambuf_iterator<char>(is)), std::istreambuf_iterator<char>());
  EXPECT_EQ(body.size(), count * 15);
  std::vector<WorldPoint> pts(count);
  for (std::size_t i = 0; i < count && (i + 1) * 15 <= body.size(); ++i) {
    const unsigned char* b = reinterpret_cast<const unsigned char*>(body.data()) + i * 15;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t bits = static_cast<std::uint32_t>(b[4 * k]) |
                                 static_cast<std::uint32_t>(b[4 * k + 1]) << 8 |
                                 static_cast<std::uint32_t>(b[4 * k + 2]) << 16 |
                                 static_cast<std::uint32_t>(b[4 * k + 3]) << 24;
      std::memcpy(&pts[i].p_world[k], &bits, 4);
    }
    pts[i].rgb = {b[12], b[13], b[14]};
  }
  return pts;
}

struct SmallRun {
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  Trajectory trajectory;
  SmallRun() {
    for (std::uint64_t id = 0; id < 3; ++id) {
      Keyframe kf;
      kf.id = id;
      kf.t = 100.0 + static_cast<double>(id);
      kf.T_world_cam.linear() =
          Eigen::AngleAxisd(0.2 * static_cast<double>(id), Eigen::Vector3d::UnitZ())
              .toRotationMatrix();
      kf.T_world_cam.translation() = Eigen::Vector3d(0.5 * static_cast<double>(id), 0.1, 0.3);
      kf.points = map.insertKeyframe(planeFrame(static_cast<std::uint16_t>(1500 + 500 * id)),
                                     kf.T_world_cam);
      store.add(kf);
    }
    for (int k = 0; k <= 20; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.05 * k, 0.01 * k, 0.0);
      trajectory.push_back(StampedPose::fromIsometry(100.0 + 0.1 * k, T));
    }
  }
};

Eigen::Matrix4d matrixOf(const mrpt::poses::CPose3D& p) {
  return p.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
}

}  // namespace

TEST(MapExport, PlyHoldsEveryPointBitExact) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_ply");
  std::vector<WorldPoint> pts(3);
  pts[0] = {Eigen::Vector3f(1.5f, -2.25f, 0.125f), {255, 0, 7}};
  pts[1] = {Eigen::Vector3f(-1e-3f, 3.0e4f, -0.0f), {1, 2, 3}};
  pts[2] = {Eigen::Vector3f(0.1f, 0.2f, 0.3f), {128, 128, 128}};
  writePly(dir + "/three.ply", pts);
  const std::vector<WorldPoint> back = readPly(dir + "/three.ply");
  ASSERT_EQ(back.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].p_world, pts[i].p_world);
    EXPECT_EQ(back[i].rgb, pts[i].rgb);
  }
  SmallRun run;
  writePly(dir + "/map.ply", run.map);
  const std::vector<WorldPoint> map_back = readPly(dir + "/map.ply");
  ASSERT_EQ(map_back.size(), run.map.pointCount());
  for (std::size_t i = 0; i < map_back.size(); ++i) {
    ASSERT_EQ(map_back[i].p_world, run.map.points()[i].p_world);
    ASSERT_EQ(map_back[i].rgb, run.map.points()[i].rgb);
  }
  writePly(dir + "/empty.ply", std::vector<WorldPoint>{});
  EXPECT_TRUE(readPly(dir + "/empty.ply").empty());
  EXPECT_THROW(writePly("/nonexistent_dir_rgbdi/map.ply", pts), rgbdi::IoError);
}

TEST(MapExport, PointsMapDeserialisesWithMrpt) {
  SmallRun run;
  const std::string path = rgbdi::test::makeTempDir("rgbdi_pm") + "/map.pointsmap";
  writePointsMap(path, run.map);
  mrpt::maps::CColouredPointsMap back;
  mrpt::io::CFileGZInputStream in(path);
  auto archive = mrpt::serialization::archiveFrom(in);
  archive >> back;
  ASSERT_EQ(back.size(), run.map.pointCount());
  for (std::size_t i = 0; i < back.size(); ++i) {
    float x, y, z, r, g, b;
    back.getPointRGB(i, x, y, z, r, g, b);
    const WorldPoint& p = run.map.points()[i];
    ASSERT_EQ(Eigen::Vector3f(x, y, z), p.p_world);
    ASSERT_NEAR(r * 255.0f, p.rgb[0], 0.01f);
    ASSERT_NEAR(g * 255.0f, p.rgb[1], 0.01f);
    ASSERT_NEAR(b * 255.0f, p.rgb[2], 0.01f);
  }
}

TEST(MapExport, SceneOpensWithMrptAndHoldsPointsTrajectoryAndKeyframes) {
  SmallRun run;
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_scene");
  Trajectory gt = run.trajectory;
  for (StampedPose& s : gt) s.p.y() += 0.05;
  writeScene(dir + "/scene.3Dscene", run.map, run.trajectory, run.store, SceneOptions{}, &gt);
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(dir + "/scene.3Dscene"));

  auto cloud =
      std::dynamic_pointer_cast<mrpt::opengl::CPointCloudColoured>(scene.getByName("map_points"));
  ASSERT_TRUE(cloud);
  ASSERT_EQ(cloud->size(), run.map.pointCount());
  for (std::size_t i = 0; i < cloud->size(); i += 97) {
    const mrpt::math::TPoint3Df& q = cloud->getPoint3Df(i);
    const WorldPoint& p = run.map.points()[i];
    EXPECT_EQ(Eigen::Vector3f(q.x, q.y, q.z), p.p_world);
    const mrpt::img::TColor c = cloud->getPointColor(i);
    EXPECT_EQ((Rgb{c.R, c.G, c.B}), p.rgb);
  }
  auto traj = std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("trajectory"));
  ASSERT_TRUE(traj);
  EXPECT_EQ(traj->getLineCount(), run.trajectory.size() - 1);
  double x0, y0, z0, x1, y1, z1;
  traj->getLineByIndex(3, x0, y0, z0, x1, y1, z1);
  EXPECT_NEAR(x0, run.trajectory[3].p.x(), 1e-6);
  EXPECT_NEAR(y1, run.trajectory[4].p.y(), 1e-6);
  auto truth =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("ground_truth"));
  ASSERT_TRUE(truth);
  EXPECT_EQ(truth->getLineCount(), gt.size() - 1);
  auto frames =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("keyframes"));
  ASSERT_TRUE(frames);
  // One line set per axis holding every keyframe's axis: from the camera centre along the
  // camera's x / y / z, keyframe_axis_m long.
  ASSERT_EQ(frames->size(), 3u);
  const char* axis_name[3] = {"keyframes_x", "keyframes_y", "keyframes_z"};
  for (int a = 0; a < 3; ++a) {
    auto axis =
        std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(frames->getByName(axis_name[a]));
    ASSERT_TRUE(axis) << axis_name[a];
    ASSERT_EQ(axis->getLineCount(), run.store.size());
    for (std::size_t k = 0; k < run.store.size(); ++k) {
      const Eigen::Isometry3d& T = run.store.at(k).T_world_cam;
      const Eigen::Vector3d tip =
          T.translation() + SceneOptions().keyframe_axis_m * T.linear().col(a);
      axis->getLineByIndex(k, x0, y0, z0, x1, y1, z1);
      EXPECT_TRUE(Eigen::Vector3d(x0, y0, z0).isApprox(T.translation(), 1e-5)) << k;
      EXPECT_TRUE(Eigen::Vector3d(x1, y1, z1).isApprox(tip, 1e-5)) << k;
    }
  }
  EXPECT_TRUE(scene.getByName("ground_grid"));
  // Lines stand out from the points: thicker, in a colour of their own.
  EXPECT_EQ(traj->getLineWidth(), 4.0f);
  EXPECT_EQ(traj->getColor_u8(), mrpt::img::TColor(255, 0, 255));
  // The initial view looks at the centre of the drawn content from a distance that shows it.
  auto camera = scene.getByClass<mrpt::opengl::CCamera>();
  ASSERT_TRUE(camera);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  for (const auto& p : run.map.points()) {
    lo = lo.cwiseMin(p.p_world.cast<double>());
    hi = hi.cwiseMax(p.p_world.cast<double>());
  }
  for (const auto& p : run.trajectory) {
    lo = lo.cwiseMin(p.p);
    hi = hi.cwiseMax(p.p);
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  EXPECT_NEAR(camera->getPointingAtX(), centre.x(), 1e-4);
  EXPECT_NEAR(camera->getPointingAtY(), centre.y(), 1e-4);
  EXPECT_NEAR(camera->getPointingAtZ(), centre.z(), 1e-4);
  EXPECT_NEAR(camera->getZoomDistance(), 1.5 * std::max(1.0, (hi - lo).norm()), 1e-3);

  writeScene(dir + "/no_gt.3Dscene", run.map, run.trajectory, run.store, SceneOptions{});
  mrpt::opengl::COpenGLScene scene2;
  ASSERT_TRUE(scene2.loadFromFile(dir + "/no_gt.3Dscene"));
  EXPECT_FALSE(scene2.getByName("ground_truth"));
  EXPECT_TRUE(scene2.getByName("map_points"));
}

TEST(MapExport, SimpleMapHoldsPosesAndObservations) {
  std::vector<SimpleMapEntry> entries;
  for (int k = 0; k < 2; ++k) {
    auto obs = mrpt::obs::CObservation3DRangeScan::Create();
    obs->sensorLabel = "RGBD";
    obs->hasRangeImage = true;
    obs->rangeImage_setSize(3, 4);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        obs->rangeImage(r, c) = static_cast<std::uint16_t>(1000 * k + 10 * r + c);
    SimpleMapEntry e;
    e.T_world_body.linear() =
        Eigen::AngleAxisd(0.4 * k + 0.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    e.T_world_body.translation() = Eigen::Vector3d(k, -2.0 * k, 0.5);
    e.observation = obs;
    entries.push_back(e);
  }
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_sm");
  writeSimpleMap(dir + "/keyframes.simplemap", entries);
  mrpt::maps::CSimpleMap back;
  ASSERT_TRUE(back.loadFromFile(dir + "/keyframes.simplemap"));
  ASSERT_EQ(back.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    mrpt::poses::CPose3DPDF::Ptr pose;
    mrpt::obs::CSensoryFrame::Ptr frame;
    back.get(k, pose, frame);
    EXPECT_TRUE(matrixOf(pose->getMeanVal()).isApprox(entries[k].T_world_body.matrix(), 1e-12));
    ASSERT_EQ(frame->size(), 1u);
    auto obs = frame->getObservationByClass<mrpt::obs::CObservation3DRangeScan>();
    ASSERT_TRUE(obs);
    EXPECT_EQ(obs->sensorLabel, "RGBD");
    EXPECT_EQ(obs->rangeImage(2, 3), 1000 * k + 23);
  }
  entries[1].observation.reset();
  try {
    writeSimpleMap(dir + "/bad.simplemap", entries);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("entry 1 has no observation"), std::string::npos);
  }
}

namespace {

/// True when some pixel within `radius` of (col, row) satisfies `pred`.
template <typename Pred>
bool pixelNear(const cv::Mat& img, const Eigen::Vector2d& px, int radius, Pred pred) {
  const int c0 = static_cast<int>(std::lround(px.x())), r0 = static_cast<int>(std::lround(px.y()));
  for (int r = r0 - radius; r <= r0 + radius; ++r)
    for (int c = c0 - radius; c <= c0 + radius; ++c)
      if (r >= 0 && c >= 0 && r < img.rows && c < img.cols && pred(img.at<cv::Vec3b>(r, c)))
        return true;
  return false;
}

}  // namespace

TEST(TrajectoryPlot, DrawsBothViewsWithErrorColouredEstimateAndGroundTruth) {
  Trajectory est, gt;
  for (int k = 0; k <= 40; ++k) {
    StampedPose s;
    s.t = 10.0 + 0.1 * k;
    s.p = Eigen::Vector3d(0.05 * k, 0.0, 0.002 * k);
    est.push_back(s);
    s.p.y() += (k < 20 ? 0.0 : 0.1);  // zero error on the first half, 0.1 m on the second
    gt.push_back(s);
  }
  gt.erase(gt.begin() + 5);  // pose 5 has no ground-truth partner
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_plot");
  TrajectoryPlotOptions o;
  const TrajectoryPlotInfo info = plotTrajectory(dir + "/trajectory.png", est, &gt, o);
  EXPECT_EQ(info.matched, 40u);
  EXPECT_NEAR(info.max_error_m, 0.1, 1e-12);
  EXPECT_NEAR(info.rmse_m, std::sqrt(21 * 0.01 / 40), 1e-12);
  const cv::Mat img = cv::imread(dir + "/trajectory.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, info.width);
  EXPECT_EQ(img.rows, info.height);
  EXPECT_EQ(info.width, 2 * (70 + 600 + 20));

  const PlotPanel& top = info.panels[0];
  const PlotPanel& side = info.panels[1];
  EXPECT_EQ(top.px_per_m_h, top.px_per_m_v);    // equal axes in the top view
  EXPECT_GT(side.px_per_m_v, side.px_per_m_h);  // z exaggerated in the side view
  // Zero-error part: the low end of TURBO (dark purple, BGR about (59, 18, 48)).
  auto low = [](const cv::Vec3b& c) { return c[0] > 40 && c[0] > c[2] + 5 && c[1] < 40; };
  // Largest error: the high end of TURBO (dark red: red channel dominant, little green/blue).
  auto high = [](const cv::Vec3b& c) { return c[2] > 90 && c[1] < 30 && c[0] < 30; };
  auto grey = [](const cv::Vec3b& c) { return c[0] == c[1] && c[1] == c[2] && c[0] < 150; };
  EXPECT_TRUE(pixelNear(img, top.toPixel(est[10].p), 1, low));
  EXPECT_TRUE(pixelNear(img, top.toPixel(est[30].p), 1, high));
  EXPECT_FALSE(pixelNear(img, top.toPixel(est[30].p), 1, low));
  EXPECT_TRUE(pixelNear(img, top.toPixel(gt[30].p), 1, grey));
  EXPECT_TRUE(pixelNear(img, side.toPixel(est[30].p), 1, high));
  // Pixel mapping: the estimate's x range is centred in the panel.
  const double mid = 0.5 * (top.toPixel(est.front().p).x() + top.toPixel(est.back().p).x());
  EXPECT_NEAR(mid, top.area.x + top.area.width / 2.0, 1e-9);

  // Without ground truth the estimate is plain blue and no error statistics are given.
  const TrajectoryPlotInfo plain = plotTrajectory(dir + "/plain.png", est, nullptr, o);
  EXPECT_EQ(plain.matched, 0u);
  const cv::Mat img2 = cv::imread(dir + "/plain.png", cv::IMREAD_COLOR);
  ASSERT_FALSE(img2.empty());
  auto blue = [](const cv::Vec3b& c) { return c[0] > 150 && c[2] < 80; };
  EXPECT_TRUE(pixelNear(img2, plain.panels[0].toPixel(est[30].p), 1, blue));
  EXPECT_FALSE(pixelNear(img2, plain.panels[0].toPixel(est[30].p), 1, high));
}

TEST(TrajectoryPlot, BadInputIsRejected) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_plot_bad");
  EXPECT_THROW(plotTrajectory(dir + "/a.png", Trajectory{}, nullptr, {}), std::invalid_argument);
  Trajectory est(3);
  est[1].p.x() = std::nan("");
  try {
    plotTrajectory(dir + "/a.png", est, nullptr, {});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("estimate pose 1 is not finite"), std::string::npos)
        << e.what();
  }
  Trajectory single(1);
  EXPECT_NO_THROW(plotTrajectory(dir + "/single.png", single, nullptr, {}));  // a robot at rest
  EXPECT_FALSE(cv::imread(dir + "/single.png").empty());
  EXPECT_THROW(plotTrajectory("/nonexistent_dir_rgbdi/t.png", single, nullptr, {}), rgbdi::IoError);
}
