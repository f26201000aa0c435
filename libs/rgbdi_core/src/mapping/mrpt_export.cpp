// MRPT-native exports: serialized coloured points map, 3-D scene and simple map.
#include <mrpt/maps/CColouredPointsMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/opengl/CCamera.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "mapping/pose_check.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/gzip_file_writer.h"
#include "rgbdi/mapping/map_export.h"

namespace rgbdi::mapping {
namespace {

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T) {
  return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble44(T.matrix()));
}

/// Runs an MRPT writer on the temporary file; MRPT reports failures with exceptions or false.
void writeWithMrpt(const std::string& path, const std::string& what,
                   const std::function<bool(const std::string&)>& write) {
  writeFileAtomicallyVia(path, [&](const std::string& tmp) {
    bool ok = false;
    try {
      ok = write(tmp);
    } catch (const std::exception& e) {
      throw IoError(path + ": MRPT could not write the " + what + ": " + e.what());
    }
    if (!ok) throw IoError(path + ": MRPT could not write the " + what);
  });
}

/// MRPT's gzip serialization (what CFileGZOutputStream and COpenGLScene::saveToFile write, read
/// back the same way), compressed by libdeflate (io::GzipFileWriter: half the CPU).
bool serializeGz(const std::string& tmp, const mrpt::serialization::CSerializable& object) {
  io::GzipFileWriter out(tmp);
  auto archive = mrpt::serialization::archiveFrom(out);
  archive << object;
  out.close();
  return true;
}

float unit(std::uint8_t c) { return static_cast<float>(c) / 255.0f; }

mrpt::opengl::CSetOfLines::Ptr polyline(const Trajectory& trajectory, const std::string& name,
                                        float r, float g, float b) {
  auto lines = mrpt::opengl::CSetOfLines::Create();
  lines->setName(name);
  lines->setColor(r, g, b);
  lines->setLineWidth(4.0f);  // thicker than the 2-px map points: the path stays visible
  for (std::size_t k = 1; k < trajectory.size(); ++k) {
    const Eigen::Vector3d& a = trajectory[k - 1].p;
    const Eigen::Vector3d& c = trajectory[k].p;
    lines->appendLine(a.x(), a.y(), a.z(), c.x(), c.y(), c.z());
  }
  return lines;
}

void checkFinite(const Trajectory& trajectory, const std::string& path, const char* which) {
  for (std::size_t k = 0; k < trajectory.size(); ++k)
    if (!trajectory[k].p.allFinite() || !trajectory[k].q.coeffs().allFinite())
      throw std::invalid_argument("writeScene " + path + ": " + which + " pose " +
                                  std::to_string(k) + " is not finite");
}

}  // namespace

void writePointsMap(const std::string& path, const PointMap& map) {
  mrpt::maps::CColouredPointsMap points;
  points.reserve(map.pointCount());
  for (const WorldPoint& p : map.points())
    points.insertPointRGB(p.p_world.x(), p.p_world.y(), p.p_world.z(), unit(p.rgb[0]),
                          unit(p.rgb[1]), unit(p.rgb[2]));
  writeWithMrpt(path, "coloured points map",
                [&](const std::string& tmp) { return serializeGz(tmp, points); });
}

void writeScene(const std::string& path, const PointMap& map, const Trajectory& trajectory,
                const KeyframeStore& keyframes, const SceneOptions& options,
                const Trajectory* ground_truth, const std::vector<SceneSegment>* loop_edges,
                const std::vector<mrpt::opengl::CRenderizable::Ptr>* extra_objects) {
  checkFinite(trajectory, path, "trajectory");
  if (ground_truth) checkFinite(*ground_truth, path, "ground-truth");
  mrpt::opengl::COpenGLScene scene;

  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  cloud->setName("map_points");
  cloud->setPointSize(2.0f);
  cloud->reserve(map.pointCount());
  // The ground grid spans everything drawn, rounded out to whole metres.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const WorldPoint& p : map.points()) {
    cloud->push_back(p.p_world.x(), p.p_world.y(), p.p_world.z(), unit(p.rgb[0]), unit(p.rgb[1]),
                     unit(p.rgb[2]));
    lo = lo.cwiseMin(p.p_world.cast<double>());
    hi = hi.cwiseMax(p.p_world.cast<double>());
  }
  scene.insert(cloud);

  for (const StampedPose& s : trajectory) {
    lo = lo.cwiseMin(s.p);
    hi = hi.cwiseMax(s.p);
  }
  // Saturated magenta / yellow: colours that real-world map points rarely have.
  scene.insert(polyline(trajectory, "trajectory", 1.0f, 0.0f, 1.0f));
  if (ground_truth) scene.insert(polyline(*ground_truth, "ground_truth", 1.0f, 0.85f, 0.0f));

  // Keyframe axes (x red, y green, z blue, camera frame) as three line sets holding every
  // keyframe: one stock corner object per keyframe cost 3.6 kB each (15 MB for a 10-minute run,
  // the largest allocation while the outputs are written) and as many draw calls in a viewer.
  auto frames = mrpt::opengl::CSetOfObjects::Create();
  frames->setName("keyframes");
  const float axis_colour[3][3] = {{1.0f, 0.0f, 0.0f}, {0.0f, 0.8f, 0.0f}, {0.0f, 0.0f, 1.0f}};
  const char* axis_name[3] = {"keyframes_x", "keyframes_y", "keyframes_z"};
  for (int a = 0; a < 3; ++a) {
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName(axis_name[a]);
    lines->setColor(axis_colour[a][0], axis_colour[a][1], axis_colour[a][2]);
    lines->setLineWidth(2.0f);
    lines->reserve(keyframes.keyframes().size());
    for (const Keyframe& kf : keyframes.keyframes()) {
      const Eigen::Vector3d o = kf.T_world_cam.translation();
      const Eigen::Vector3d e = o + options.keyframe_axis_m * kf.T_world_cam.linear().col(a);
      lines->appendLine(o.x(), o.y(), o.z(), e.x(), e.y(), e.z());
    }
    frames->insert(lines);
  }
  scene.insert(frames);

  if (loop_edges && !loop_edges->empty()) {
    auto lines = mrpt::opengl::CSetOfLines::Create();
    lines->setName("loop_edges");
    lines->setColor(1.0f, 0.1f, 0.1f);
    lines->setLineWidth(2.0f);
    for (const SceneSegment& e : *loop_edges)
      lines->appendLine(e.first.x(), e.first.y(), e.first.z(), e.second.x(), e.second.y(),
                        e.second.z());
    scene.insert(lines);
  }

  if (extra_objects)
    for (const auto& object : *extra_objects) scene.insert(object);

  if (!(lo.allFinite() && hi.allFinite())) {
    lo = Eigen::Vector3d::Constant(-1.0);
    hi = Eigen::Vector3d::Constant(1.0);
  }
  auto grid = mrpt::opengl::CGridPlaneXY::Create(
      static_cast<float>(std::floor(lo.x())), static_cast<float>(std::ceil(hi.x())),
      static_cast<float>(std::floor(lo.y())), static_cast<float>(std::ceil(hi.y())),
      static_cast<float>(lo.z()), 1.0f);
  grid->setName("ground_grid");
  grid->setColor(0.6f, 0.6f, 0.6f);
  scene.insert(grid);

  // The viewer opens looking down at the centre of everything drawn from a distance that shows
  // all of it (a CCamera in the main viewport sets the initial view).
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double extent = std::max(1.0, (hi - lo).norm());
  auto camera = mrpt::opengl::CCamera::Create();
  camera->setPointingAt(static_cast<float>(centre.x()), static_cast<float>(centre.y()),
                        static_cast<float>(centre.z()));
  camera->setZoomDistance(static_cast<float>(1.5 * extent));
  camera->setAzimuthDegrees(-90.0f);
  camera->setElevationDegrees(60.0f);
  scene.insert(camera);

  writeWithMrpt(path, "3-D scene", [&](const std::string& tmp) { return serializeGz(tmp, scene); });
}

void writeSimpleMap(const std::string& path, const std::vector<SimpleMapEntry>& entries) {
  mrpt::maps::CSimpleMap simple_map;
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const SimpleMapEntry& e = entries[k];
    if (!e.observation)
      throw std::invalid_argument("writeSimpleMap " + path + ": entry " + std::to_string(k) +
                                  " has no observation");
    if (!detail::isRigid(e.T_world_body))
      throw std::invalid_argument("writeSimpleMap " + path + ": entry " + std::to_string(k) +
                                  " has a pose that is not a finite rigid transform");
    auto pose = mrpt::poses::CPose3DPDFGaussian::Create(toCPose3D(e.T_world_body));
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(e.observation);
    simple_map.insert(pose, frame);
  }
  writeWithMrpt(path, "simple map",
                [&](const std::string& tmp) { return simple_map.saveToFile(tmp); });
}

}  // namespace rgbdi::mapping
