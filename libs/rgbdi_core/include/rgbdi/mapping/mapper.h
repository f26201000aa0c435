// The mapping stage as one object: keyframes whose poses are final for the odometry come in with
// their images; their depth goes into the point octree (and the occupancy OctoMap), the keyframe
// store keeps their features, descriptors and kept points; after a pose-graph solve correct()
// moves the keyframes and the map follows them (paper section 4.5).
//
// Keyframes seen from an already mapped viewpoint add no points (viewpoint_index.h), so the map
// grows with the explored space, not with time. The occupancy map is ray cast once, by finish(),
// from the keyframes' final poses: casting at insertion (with the odometry's pose) had to be
// redone at the end whenever a loop correction moved keyframes, which every loop-closing run's
// final correction does, so half of that work was always thrown away. Only the written map.bt
// and map directory read it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "rgbdi/mapping/viewpoint_index.h"

namespace rgbdi::mapping {

/// What one correct() call did.
struct MapCorrection {
  std::size_t keyframes_moved = 0;  ///< keyframes whose pose changed
  RebuildReport rebuild;            ///< the point-map update (empty when nothing moved)
  double milliseconds = 0.0;        ///< wall-clock time of the whole correction
};

/// Points a keyframe added to the map when it was inserted (later drops not subtracted).
struct KeyframeInsertion {
  std::uint64_t id = 0;
  double t = 0.0;  ///< [s] keyframe stamp
  std::size_t points = 0;
};

struct MapperStats {
  std::size_t keyframes = 0;
  std::size_t keyframes_adding_points = 0;
  std::size_t corrections = 0;       ///< correct() calls that moved keyframes
  double insert_ms_total = 0.0;      ///< addKeyframe CPU time (mapping thread), summed
  double correction_ms_total = 0.0;  ///< correct() wall-clock time, summed
  double correction_ms_max = 0.0;
  std::size_t points_at_last_correction = 0;
  double occupancy_rebuild_ms =
      0.0;  ///< finish()'s occupancy ray casting, CPU time (0 if not needed)
};

class Mapper {
 public:
  /// build_occupancy = false: no occupancy map at all (no map.bt).
  Mapper(const MappingOptions& options, bool build_occupancy);

  /// Adds a keyframe (its `points` are filled here; `T_world_cam` is the best estimate now).
  /// Throws std::invalid_argument for a duplicate id or an unusable frame (see PointMap).
  void addKeyframe(Keyframe keyframe, const RgbdFrame& frame);

  /// Starts from a saved map (before any addKeyframe): every keyframe with its kept points goes
  /// into the store, the point map and the viewpoint index at its saved pose (and into the
  /// occupancy map at finish()). Throws std::logic_error when keyframes were added already,
  /// std::invalid_argument for a duplicate id.
  void restore(const KeyframeStore& saved);

  /// Moves keyframes to corrected camera poses (id, T_world_cam); ids not in the store are
  /// ignored (keyframes the mapper has not received yet), and so are corrections smaller than
  /// correction_min_shift_m / correction_min_rotation_deg. Updates the point map for the moved
  /// keyframes only (PointMap::update: the result of a full rebuild, isolated leaves dropped).
  MapCorrection correct(const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& poses);

  /// Ray casts the occupancy map from every stored keyframe at its current pose, in insertion
  /// order (once, at the end of a run; again only after further keyframes or corrections).
  void finish();

  const KeyframeStore& store() const { return store_; }
  const PointMap& pointMap() const { return points_; }
  /// nullptr when built without occupancy; empty until finish().
  const OccupancyMap* occupancy() const { return occupancy_.get(); }
  const MapperStats& stats() const { return stats_; }
  /// Every addKeyframe call in order: how the map grew (e.g. points added per lap).
  const std::vector<KeyframeInsertion>& insertions() const { return insertions_; }
  /// Heap bytes of the point octree + keyframe store + occupancy map.
  std::size_t memoryBytes() const;

 private:
  void rebuildViewpoints();

  MappingOptions options_;
  KeyframeStore store_;
  PointMap points_;
  std::unique_ptr<OccupancyMap> occupancy_;
  bool occupancy_outdated_ = false;
  ViewpointIndex viewpoints_;
  std::vector<std::uint64_t> adding_ids_;  ///< keyframes that added points (viewpoints), by id
  MapperStats stats_;
  std::vector<KeyframeInsertion> insertions_;
};

}  // namespace rgbdi::mapping
