// The octree point mapper (paper section 4.5, Figure 6, Table 2).
//
// Each keyframe's depth image is subsampled on a pixel grid (MappingOptions grid_*, depth range
// (depth_min_m, depth_max_m)), the points are transformed into the world and inserted into the
// leaves of an OctoMap-keyed octree (octree_resolution_m; only the leaves are kept, in hashed
// blocks: the map never needs inner nodes), which hold at most max_points_per_leaf points.
// Points arriving at a full leaf are rejected and are not returned, so the keyframe keeps
// only the points the map holds. After keyframe poses change (pose-graph update, loop closure,
// reload), rebuild() re-inserts every keyframe's kept points at the corrected poses and discards
// the isolated leaves: fewer than min_points_per_leaf_rebuild points within the 3 x 3 x 3 cells
// of twice the leaf size around the leaf, from the map and from the keyframes. update() gives the
// same result touching only the keyframes that moved (the cost of a loop grows with what the loop
// moved, not with the map). Memory is bounded by the scene: points <= leaves x
// max_points_per_leaf.
//
// Typical use:
//   PointMap map(options);
//   kf.points = map.insertKeyframe(frame, kf.T_world_cam, kf.id);  store.add(kf);
//   ... store.setPose(id, corrected) for the moved keyframes ...;  map.update(store, moved_ids);
//   (or map.rebuild(store): same result, re-inserts everything; the only way after a reload)
//   writePly("map.ply", map);
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/map_point.h"
#include "rgbdi/mapping/mapping_options.h"

namespace rgbdi::mapping {

/// Counters over all insertions since construction or clear() (rebuilds do not change them).
/// candidates is the map size without any filter ("origin points" of the paper's Table 2).
struct PointMapStats {
  std::uint64_t keyframes = 0;       ///< insertKeyframe / insertPoints calls
  std::uint64_t grid_points = 0;     ///< grid pixels visited
  std::uint64_t no_depth = 0;        ///< grid pixels with depth 0
  std::uint64_t out_of_range = 0;    ///< grid pixels with depth outside (depth_min_m, depth_max_m)
  std::uint64_t candidates = 0;      ///< points offered to the octree
  std::uint64_t outside_extent = 0;  ///< beyond the octree's addressable extent (+-655 m at 2 cm)
  std::uint64_t rejected_full_leaf = 0;  ///< dropped because their leaf was full
  std::uint64_t accepted = 0;            ///< inserted (and returned to the keyframe)
};

/// What one rebuild() did.
struct RebuildReport {
  std::size_t keyframes = 0;
  std::size_t input_points = 0;        ///< kept points of all keyframes before the rebuild
  std::size_t rejected_full_leaf = 0;  ///< no longer fit at the corrected poses
  std::size_t outside_extent = 0;
  std::size_t sparse_leaves_removed = 0;  ///< isolated leaves (see rebuild())
  std::size_t sparse_points_removed = 0;
  std::size_t kept_points = 0;  ///< map size after the rebuild
  double seconds = 0.0;         ///< wall-clock time of the rebuild
};

class PointMap {
 public:
  /// keyframe_id of points whose keyframe the map does not know (then only rebuild() applies).
  static constexpr std::uint64_t kUntrackedKeyframe = ~std::uint64_t{0};

  /// Validates the options (throws ConfigError).
  explicit PointMap(const MappingOptions& options);
  ~PointMap();
  PointMap(PointMap&&) noexcept;
  PointMap& operator=(PointMap&&) noexcept;
  PointMap(const PointMap&) = delete;
  PointMap& operator=(const PointMap&) = delete;

  const MappingOptions& options() const;

  /// Subsamples the frame's depth (aligned to colour: colour intrinsics; otherwise the depth
  /// intrinsics and T_color_depth), inserts the points at T_world_cam (colour camera in the
  /// world) and returns the accepted ones in the colour camera frame, to be kept by the keyframe.
  /// Throws std::invalid_argument naming the frame when it cannot be used or the pose is not a
  /// finite rigid transform.
  /// With a keyframe id (inserted once per id) the map remembers which keyframe each point came
  /// from, which update() needs; the returned points must become that keyframe's kept points.
  std::vector<MapPoint> insertKeyframe(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam,
                                       std::uint64_t keyframe_id);
  std::vector<MapPoint> insertKeyframe(const RgbdFrame& frame,
                                       const Eigen::Isometry3d& T_world_cam);
  /// Inserts points given in the camera frame; returns the accepted ones (in input order).
  std::vector<MapPoint> insertPoints(const std::vector<MapPoint>& points_cam,
                                     const Eigen::Isometry3d& T_world_cam,
                                     std::uint64_t keyframe_id = kUntrackedKeyframe);

  /// Rebuilds the map from the keyframes' kept points at their current poses (in id order),
  /// drops points that no longer fit and isolated leaves (fewer than min_points_per_leaf_rebuild
  /// points in the 3 x 3 x 3 cells of twice the leaf size around the leaf), and removes the dropped
  /// points from the keyframes too.
  RebuildReport rebuild(KeyframeStore& store);
  /// The same result as rebuild(store) when only the keyframes in `moved_ids` changed pose since
  /// their points were placed (ids the map holds no points of are skipped): their points leave
  /// their leaves and are re-inserted at the new poses; a full leaf keeps its first
  /// max_points_per_leaf points in (keyframe id, point index) order, the order rebuild() inserts
  /// them in; the isolated-leaf rule is evaluated around the cells where points were added or
  /// removed since it last ran (insertions included), which covers every leaf whose verdict can
  /// differ. Leaves, their points and every keyframe's kept points equal rebuild()'s; the order
  /// of points() differs. Throws std::logic_error when a point was inserted without a keyframe
  /// id, or the map and the store disagree (a keyframe's point count, a keyframe not in the
  /// store); std::invalid_argument for a moved id not in the store.
  RebuildReport update(KeyframeStore& store, const std::vector<std::uint64_t>& moved_ids);
  /// True when setPose() was called on the store since this map was last rebuilt from it (or
  /// since construction). A store just read by KeyframeStore::load always needs rebuild().
  bool isOutdated(const KeyframeStore& store) const;

  /// Removes every point and resets the statistics.
  void clear();

  std::size_t pointCount() const;
  std::size_t leafCount() const;
  /// Points of the map in insertion order (world frame).
  const std::vector<WorldPoint>& points() const;
  /// Number of points in the leaf containing p_world (0 when there is none).
  std::size_t pointsInLeafAt(const Eigen::Vector3d& p_world) const;
  /// Centre of the leaf containing p_world (for tests and tools). Throws std::invalid_argument
  /// beyond the map's extent.
  Eigen::Vector3d leafCenterAt(const Eigen::Vector3d& p_world) const;

  const PointMapStats& stats() const;
  const RebuildReport& lastRebuild() const;
  /// Estimated heap + object bytes (octree nodes, leaf records, points).
  std::size_t memoryBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::mapping
