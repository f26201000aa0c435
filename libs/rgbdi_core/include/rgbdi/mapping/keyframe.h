// A keyframe as the mapping stage keeps it: pose, stamp, tracked features with ids and 2-D/3-D
// positions, optional descriptors (for loop detection), and the map points it contributed.
// No image is kept: memory per keyframe is bounded by the feature and grid sizes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbdi/mapping/map_point.h"

namespace rgbdi::mapping {

/// One tracked feature seen in the keyframe. Single precision (1e-4 px, 0.5 um at 6 m): the
/// store keeps every keyframe of a session (about 150 features each), and 32 bytes per feature
/// instead of 64 halve its size; nothing computes with these after the keyframe is stored.
struct KeyframeFeature {
  std::uint64_t id = 0;                             ///< tracker id (stable across frames)
  Eigen::Vector2f uv = Eigen::Vector2f::Zero();     ///< distorted pixel position [px]
  bool has_position = false;                        ///< p_cam is known (depth or triangulation)
  Eigen::Vector3f p_cam = Eigen::Vector3f::Zero();  ///< position in the camera frame [m]
};

/// Binary descriptors of keypoints of the keyframe (e.g. BRIEF/ORB for a bag-of-words loop
/// detector). Descriptor k occupies data[k * bytes_per_descriptor, (k+1) * bytes_per_descriptor).
struct DescriptorSet {
  std::string type;  ///< e.g. "BRIEF-256"; empty when there are none
  std::uint32_t bytes_per_descriptor = 0;
  std::vector<Eigen::Vector2f> keypoints_uv;  ///< distorted pixel position of each keypoint [px]
  /// Depth-backed position of each keypoint in the colour camera optical frame [m]; all NaN when
  /// the keypoint has no valid depth. Either empty (no 3-D information at all) or size() long.
  std::vector<Eigen::Vector3f> keypoints_p_cam;
  std::vector<std::uint8_t> data;

  std::size_t size() const { return keypoints_uv.size(); }
  bool hasPoint(std::size_t k) const {
    return k < keypoints_p_cam.size() && std::isfinite(keypoints_p_cam[k].z());
  }
  /// True when data holds exactly size() descriptors and keypoints_p_cam is empty or size() long.
  bool consistent() const {
    return data.size() == keypoints_uv.size() * static_cast<std::size_t>(bytes_per_descriptor) &&
           (keypoints_p_cam.empty() || keypoints_p_cam.size() == keypoints_uv.size());
  }
};

struct Keyframe {
  std::uint64_t id = 0;           ///< unique within a KeyframeStore
  std::uint64_t frame_index = 0;  ///< RgbdFrame::index of the source frame
  double t = 0.0;                 ///< [s] stamp of the colour image
  /// Pose of the colour camera optical frame in the world.
  Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
  std::vector<KeyframeFeature> features;
  DescriptorSet descriptors;
  std::vector<MapPoint> points;  ///< kept map points (camera frame), see PointMap

  /// Heap + object bytes held by this keyframe (capacity-based estimate).
  std::size_t memoryBytes() const;
};

}  // namespace rgbdi::mapping
