// Occupancy OctoMap for path planning (map.bt, opens in octovis): free space is carved by ray
// casting from the camera to each sampled depth point, endpoints are marked occupied. Rays use
// every occupancy_grid_stride-th row and column of the point map's sampling grid (for kept point
// sets: every occupancy_grid_stride^2-th point, the others only mark their cells); points beyond
// depth_max_m still clear the free space up to depth_max_m.
#pragma once

#include <octomap/OcTree.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/map_point.h"
#include "rgbdi/mapping/mapping_options.h"

namespace rgbdi::mapping {

struct OccupancyStats {
  std::uint64_t scans = 0;  ///< frames / point sets inserted
  std::uint64_t rays = 0;   ///< rays cast
  double seconds = 0.0;     ///< wall-clock time spent ray casting
};

class OccupancyMap {
 public:
  /// Validates the options (throws ConfigError).
  explicit OccupancyMap(const MappingOptions& options);
  ~OccupancyMap();
  OccupancyMap(OccupancyMap&&) noexcept;
  OccupancyMap& operator=(OccupancyMap&&) noexcept;
  OccupancyMap(const OccupancyMap&) = delete;
  OccupancyMap& operator=(const OccupancyMap&) = delete;

  /// Ray casts the frame's subsampled depth from the colour camera at T_world_cam. Throws
  /// std::invalid_argument naming the frame like PointMap::insertKeyframe.
  void insert(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam);
  /// Ray casts points given in the camera frame (e.g. a keyframe's kept points, a subset of the
  /// full sampling grid): rays through every occupancy_grid_stride^2-th point in the given order
  /// (the same share of rays as insert()), the other points only mark their cells occupied.
  void insertPoints(const std::vector<MapPoint>& points_cam, const Eigen::Isometry3d& T_world_cam);
  /// Clears the map and ray casts every keyframe's kept points at its current pose (after pose
  /// updates: the points a keyframe keeps are a subset of its grid, so the rebuilt map has less
  /// free space carved than the incrementally built one).
  void rebuild(const KeyframeStore& store);
  void clear();

  /// Writes the maximum-likelihood occupancy tree in OctoMap's binary format (map.bt),
  /// atomically. Throws IoError.
  void write(const std::string& path) const;

  /// The OctoMap tree (inner nodes are brought up to date first: insertion defers them).
  const octomap::OcTree& tree() const;
  std::size_t leafCount() const;
  const OccupancyStats& stats() const;
  std::size_t memoryBytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::mapping
