// What loop closure knows of one keyframe: identity, odometry segment, poses, distance travelled,
// its ORB keypoints (with depth-backed 3-D points) and a coarse depth grid. No image is kept.
// Every loop module (place recognition, geometric verification, 4-DOF pose graph) works on these.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>

#include "rgbdi/loop/depth_grid.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::loop {

struct LoopKeyframe {
  std::uint64_t id = 0;  ///< keyframe id, unique within the map, increasing with time
  /// Odometry segment: the estimator restarts a segment after each reset. Poses of different
  /// segments are in frames that are not related by odometry (only a verified loop relates them).
  int segment = 0;
  double t = 0.0;  ///< [s] keyframe stamp (IMU clock)
  /// Body (IMU) pose from the odometry alone, in its segment's frame (z up, gravity along -z).
  Eigen::Isometry3d T_world_body_odom = Eigen::Isometry3d::Identity();
  /// Current best estimate of the body pose (loop-corrected); equals the odometry until a loop.
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  /// [m] path length of the odometry from the start of the run (all segments) to this keyframe.
  double travelled_m = 0.0;
  /// [s] of the odometry since the previous keyframe of its segment in loop closing that the IMU
  /// carried alone (blind frames): the pose graph's edge across it is weak.
  double bridged_s = 0.0;
  /// ORB keypoints of the colour image: distorted pixels, descriptors (type "ORB-256", 32 bytes)
  /// and depth-backed points in the colour camera frame (NaN where the keypoint has no depth).
  mapping::DescriptorSet descriptors;
  /// Coarse colour-registered depth (free-space check of verification); empty without depth.
  DepthGrid depth_grid;
};

}  // namespace rgbdi::loop
