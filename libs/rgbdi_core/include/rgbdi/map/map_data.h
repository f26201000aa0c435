// What a saved map holds, in memory: the manifest (format, calibration, descriptor type, index
// parameters, frame conventions), the keyframes of loop closing with their ORB descriptors and
// depth-backed keypoints (place recognition is rebuilt from them), the loop edges of the pose
// graph, and the mapping keyframe store (poses, features, kept points: the point map and the
// occupancy map are rebuilt from it). map_directory.h reads and writes it as DIR/map/.
//
// Frames: every pose is in the map's world frame (z up, gravity along -z); T_world_body is the
// IMU body, T_world_cam the colour camera optical frame; T_body_cam relates the two.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/loop/loop_keyframe.h"
#include "rgbdi/mapping/keyframe_store.h"

namespace rgbdi::map {

/// Format version written by saveMap (loadMap refuses any other).
constexpr int kMapFormatVersion = 2;

struct MapManifest {
  int format_version = kMapFormatVersion;
  /// Calibration the map was built with; a run with another one is refused.
  PinholeCamera camera;  ///< colour camera (intrinsics, distortion, size) of the loop keyframes
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  std::string descriptor_type;         ///< e.g. "ORB-256"
  std::uint32_t descriptor_bytes = 0;  ///< bytes per descriptor
  std::uint64_t next_keyframe_id = 0;  ///< ids of a run that extends the map start here
  int next_segment = 0;                ///< segments of a run that extends the map start here
  int sessions = 0;                    ///< runs that built this map
  /// Informational: the place-index parameters of the run that saved it (INI "key = value"
  /// lines of [loop] place_*); the index is rebuilt with the loading run's parameters.
  std::string index_parameters;
  /// When the map was built by a run evaluated against ground truth (--gt): the map frame in
  /// the ground truth's frame (position + yaw alignment of that run's final trajectory). A
  /// later run in this map is then evaluated through it, with no alignment of its own.
  bool has_groundtruth_alignment = false;
  Eigen::Isometry3d T_groundtruth_world = Eigen::Isometry3d::Identity();
  std::string world_frame = "z up, gravity along -z, metres";
  std::string pose_convention = "T_a_b maps points of frame b into frame a";
};

/// One loop edge of the saved pose graph (from = older keyframe, to = newer).
struct MapLoopEdge {
  std::uint64_t from_id = 0, to_id = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();  ///< body frames
  bool active = true;  ///< false: rolled back (kept for the record, not used)
};

struct MapData {
  MapManifest manifest;
  /// Keyframes of loop closing, by increasing id: T_world_body_odom is the odometry pose in its
  /// segment's frame, T_world_body the corrected pose in the map frame.
  std::vector<loop::LoopKeyframe> places;
  std::vector<MapLoopEdge> loops;
  mapping::KeyframeStore keyframes;  ///< T_world_cam corrected, with kept points
};

/// The content of a MapData by reference: what saveMap writes. A finished run saves its map
/// through a view of its own keyframes (SlamSystem::mapView) instead of a copy, which on a
/// 10-minute run is ~50 MB of descriptors and keyframes held twice at the end of the run.
/// The pointed-to keyframes must outlive the view.
struct MapView {
  struct Place {
    const loop::LoopKeyframe* keyframe = nullptr;  ///< its T_world_body is not used
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();  ///< saved pose (map frame)
  };
  MapManifest manifest;
  std::vector<Place> places;  ///< by increasing id
  std::vector<MapLoopEdge> loops;
  std::vector<const mapping::Keyframe*> keyframes;  ///< by increasing id

  /// The view of `map` (which must outlive it).
  static MapView of(const MapData& map);
  /// A MapData holding copies of what the view points at.
  MapData copy() const;
};

}  // namespace rgbdi::map
