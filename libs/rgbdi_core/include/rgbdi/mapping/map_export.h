// Map and scene files: map.ply (coloured points, binary little-endian PLY for MeshLab,
// CloudCompare, Open3D), map.pointsmap (serialized mrpt::maps::CColouredPointsMap),
// scene.3Dscene (mrpt::opengl::COpenGLScene for SceneViewer3D) and keyframes.simplemap
// (mrpt::maps::CSimpleMap). Every file is written atomically; failures throw IoError naming
// the path.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/opengl/CRenderizable.h>

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/map_point.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/point_map.h"

namespace rgbdi::mapping {

/// map.ply: vertices with float x, y, z [m, world] and uchar red, green, blue.
void writePly(const std::string& path, const std::vector<WorldPoint>& points);
void writePly(const std::string& path, const PointMap& map);

/// map.pointsmap: the map's points as an MRPT CColouredPointsMap, MRPT-serialized (gzip), to be
/// read with mrpt::io::CFileGZInputStream + archiveFrom(...) >> map.
void writePointsMap(const std::string& path, const PointMap& map);

/// A segment drawn in the scene, e.g. a loop edge between two keyframe positions [m, world].
using SceneSegment = std::pair<Eigen::Vector3d, Eigen::Vector3d>;

/// scene.3Dscene: the map points ("map_points", CPointCloudColoured), the trajectory
/// ("trajectory", CSetOfLines, magenta, 4 px), the ground truth when given ("ground_truth",
/// yellow), an axes frame per keyframe ("keyframes", CSetOfObjects: the colour camera optical
/// frame, z forward, not the body frame of the trajectory), the loop edges when given
/// ("loop_edges", red CSetOfLines), a ground grid ("ground_grid") and a CCamera looking at the
/// centre of all of it from a distance that shows it whole. `extra_objects` (e.g. the
/// navigation maps, navmap::sceneObjects) are inserted as they are.
void writeScene(const std::string& path, const PointMap& map, const Trajectory& trajectory,
                const KeyframeStore& keyframes, const SceneOptions& options,
                const Trajectory* ground_truth = nullptr,
                const std::vector<SceneSegment>* loop_edges = nullptr,
                const std::vector<mrpt::opengl::CRenderizable::Ptr>* extra_objects = nullptr);

/// One entry of keyframes.simplemap: the body pose and the observation taken there (e.g. a
/// CObservation3DRangeScan whose sensorPose places the camera on the body).
struct SimpleMapEntry {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  mrpt::obs::CObservation::Ptr observation;
};
/// keyframes.simplemap: poses (as exact CPose3DPDFGaussian means) + one-observation sensory
/// frames. Throws std::invalid_argument when an entry has no observation or a non-rigid pose.
void writeSimpleMap(const std::string& path, const std::vector<SimpleMapEntry>& entries);

}  // namespace rgbdi::mapping
