// Camera viewpoints of the keyframes that already put points into the map.
//
// A robot that drives the same loop again (or stands still while turning a little) sees the same
// surfaces from the same places; inserting those keyframes adds no information but, with depth
// noise and odometry drift, keeps creating new octree leaves, so the map would grow with time
// instead of with the explored space. Like RTAB-Map's linear/angular update thresholds, a keyframe
// adds points only when no mapped viewpoint lies within a distance AND a rotation angle of it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace rgbdi::mapping {

class ViewpointIndex {
 public:
  /// min_distance_m <= 0 disables the test (every viewpoint is new).
  ViewpointIndex(double min_distance_m, double min_angle_deg);

  /// True when a stored viewpoint is closer than min_distance_m and its optical frame is rotated
  /// by less than min_angle_deg relative to T_world_cam.
  bool covered(const Eigen::Isometry3d& T_world_cam) const;
  void add(const Eigen::Isometry3d& T_world_cam);
  std::size_t size() const { return count_; }

 private:
  using Key = std::int64_t;
  Key key(int ix, int iy, int iz) const;
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;

  double min_distance_m_;
  double cos_half_angle_;  ///< |quaternion dot| above this: rotation angle below the threshold
  // Hash grid with cells of min_distance_m: a neighbour within that distance is in one of the
  // 27 cells around the query, so a query costs O(1) whatever the number of keyframes.
  std::unordered_map<Key, std::vector<Eigen::Isometry3d>> cells_;
  std::size_t count_ = 0;
};

}  // namespace rgbdi::mapping
