// The saved map directory (DIR/map): saveMap writes a MapData and the tools' files into a fresh
// version directory and publishes it atomically; loadMap reads it back, refusing (MapError naming
// the file) another format version and any missing, truncated or corrupt file; checkCompatible
// refuses a map built with another calibration or descriptor type. Format: doc/maps.md.
//
// Publishing: `map_dir` is a relative symbolic link to a sibling `<name>.<n>` holding complete,
// fsync'ed files; a new save writes `<name>.tmp-<n+1>`, renames it to `<name>.<n+1>` and replaces
// the link with rename(2), then removes the older versions. A crash or kill at any moment leaves
// `map_dir` naming either the previous complete map or the new one. A `map_dir` that exists as a
// plain directory (not written by saveMap, e.g. a `cp -r` copy) is refused: it cannot be replaced
// atomically.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <functional>
#include <stdexcept>
#include <string>

#include "rgbdi/common/camera.h"
#include "rgbdi/map/map_data.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "rgbdi/output/pose_graph.h"

namespace rgbdi::map {

/// A map directory that cannot be written, read or used: the message names the file (or the
/// directory) and what is wrong.
class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// File names inside a map directory.
inline constexpr const char* kManifestFile = "manifest.json";
inline constexpr const char* kKeyframesFile = "keyframes.bin";
inline constexpr const char* kPlacesFile = "places.bin";
inline constexpr const char* kLoopsFile = "loops.txt";
inline constexpr const char* kPoseGraphFile = "pose_graph.graph";
inline constexpr const char* kPointsFile = "points.ply";
inline constexpr const char* kOccupancyFile = "map.bt";

/// Version of places.bin written by saveMap (loadMap reads this version only).
inline constexpr std::uint32_t kPlacesFileVersion = 2;

/// checkCompatible: largest accepted difference of an intrinsic [px], a distortion coefficient
/// [unitless], a rotation-matrix entry [unitless] or a translation [m] between map and run.
inline constexpr double kCalibrationTolerance = 1e-6;

/// What only users' tools read (loadMap ignores these files; the point and occupancy maps are
/// rebuilt from the keyframe store).
struct MapExtras {
  const mapping::PointMap* point_map = nullptr;      ///< points.ply when given
  const mapping::OccupancyMap* occupancy = nullptr;  ///< map.bt when given
  /// Information of the edges of pose_graph.graph (rgbdi convention, output/pose_graph.h):
  /// odometry edges join consecutive places of one segment, loop edges are the active loops.
  Eigen::Matrix<double, 6, 6> odometry_information = Eigen::Matrix<double, 6, 6>::Identity();
  Eigen::Matrix<double, 6, 6> loop_information = Eigen::Matrix<double, 6, 6>::Identity();
  /// Called after every step of the save with the step's name ("manifest.json", ...,
  /// "fsync", "renamed", "published", "cleaned"): progress reporting, and the crash-safety
  /// tests kill the process from here.
  std::function<void(const std::string& step)> after_step;
};

/// Writes `map` (and the tools' files of `extras`) as the map directory `map_dir` (see the file
/// comment). The manifest's counts and file list are filled in here; `map.manifest` supplies
/// the rest. Throws MapError when the map is inconsistent (place ids not strictly increasing,
/// descriptors of another type than the manifest's, a loop edge to an unknown place, a pose that
/// is not rigid), when `map_dir` is a plain directory, or when a file cannot be written (the
/// previous map stays published).
void saveMap(const std::string& map_dir, const MapData& map, const MapExtras& extras = {});
/// The same for the view of a map (a finished run's keyframes, not copied).
void saveMap(const std::string& map_dir, const MapView& map, const MapExtras& extras = {});

/// Reads a map directory written by saveMap. Throws MapError naming the file when the manifest
/// is missing or malformed, the format version is not kMapFormatVersion, a data file is missing,
/// has another size or checksum than the manifest says, is malformed (bad signature, version,
/// truncated records, counts that disagree with the manifest), or holds descriptors of another
/// type or size than the manifest's.
MapData loadMap(const std::string& map_dir);

/// Throws MapError (naming map_dir and listing every difference with both values) when the
/// map's camera (size, intrinsics, distortion), its T_body_cam (within kCalibrationTolerance)
/// or its descriptor type differ from the run's.
void checkCompatible(const MapManifest& m, const PinholeCamera& camera,
                     const Eigen::Isometry3d& T_body_cam, const std::string& descriptor_type,
                     const std::string& map_dir);

/// The pose graph of pose_graph.graph: one node per place (corrected pose T_world_body),
/// odometry edges between consecutive places of the same segment (from the odometry poses)
/// and the active loop edges, with the given information matrices.
output::PoseGraph mapPoseGraph(const MapData& map,
                               const Eigen::Matrix<double, 6, 6>& odometry_information,
                               const Eigen::Matrix<double, 6, 6>& loop_information);
output::PoseGraph mapPoseGraph(const MapView& map,
                               const Eigen::Matrix<double, 6, 6>& odometry_information,
                               const Eigen::Matrix<double, 6, 6>& loop_information);

}  // namespace rgbdi::map
