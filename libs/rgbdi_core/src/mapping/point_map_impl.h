// PointMap's state, shared by the insertion/rebuild code (point_map.cpp) and the incremental
// update after a loop (point_map_update.cpp). Internal to the mapping stage.
//
// Leaves are the finest cells of an OctoMap-keyed octree (key = floor(x / resolution) + 32768
// per axis, 16 bits), kept in hashed blocks of 4 x 4 x 4 (leaf_blocks.h): the point map only
// ever needs the leaf of a point, never the inner nodes. Points are dense arrays; each leaf
// threads its points in a singly linked list, each keyframe lists the map slots of its kept
// points, and a removed point's slot is filled by the last point. So a point's removal and an
// eviction from a full leaf cost O(points per leaf), and update() touches only what moved.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "mapping/cell_blocks.h"
#include "mapping/depth_grid_sampler.h"
#include "mapping/leaf_blocks.h"
#include "rgbdi/mapping/map_point.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/point_map.h"

namespace rgbdi::mapping::detail {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
static_assert(LeafBlocks::kNoLeaf == kNone);

/// OctoMap's key convention at the finest depth (16 levels): floor(coordinate / resolution)
/// + 32768, valid in [0, 65535]; the extent is +-655 m at 2 cm.
struct LeafKey {
  std::uint16_t k[3] = {0, 0, 0};

  std::uint64_t packed() const {
    return (static_cast<std::uint64_t>(k[0]) << 32) | (static_cast<std::uint64_t>(k[1]) << 16) |
           static_cast<std::uint64_t>(k[2]);
  }
  static LeafKey unpack(std::uint64_t p) {
    LeafKey key;
    key.k[0] = static_cast<std::uint16_t>(p >> 32);
    key.k[1] = static_cast<std::uint16_t>(p >> 16);
    key.k[2] = static_cast<std::uint16_t>(p);
    return key;
  }
  CellCoord cell() const { return {k[0] >> 1, k[1] >> 1, k[2] >> 1}; }
};

class LeafGrid {
 public:
  explicit LeafGrid(double resolution) : resolution_(resolution), factor_(1.0 / resolution) {}
  /// False when p is beyond the addressable extent (or not finite).
  bool keyOf(const Eigen::Vector3d& p, LeafKey& key) const {
    for (int a = 0; a < 3; ++a) {
      const double s = std::floor(factor_ * p[a]);  // as OcTreeBaseImpl::coordToKeyChecked
      if (!(s >= -kMaxVal && s < kMaxVal)) return false;
      key.k[a] = static_cast<std::uint16_t>(static_cast<int>(s) + kMaxVal);
    }
    return true;
  }
  Eigen::Vector3d centre(const LeafKey& key) const {
    Eigen::Vector3d c;
    for (int a = 0; a < 3; ++a)
      c[a] = (static_cast<double>(static_cast<int>(key.k[a]) - kMaxVal) + 0.5) * resolution_;
    return c;
  }

 private:
  static constexpr int kMaxVal = 32768;
  double resolution_, factor_;
};

/// Origin of a map point: keyframe (an ordinal of PointMapState::ordinal_id) and the index of
/// the point in that keyframe's kept points. ordinal kNone: inserted without a keyframe id.
struct PointSource {
  std::uint32_t ordinal = kNone;
  std::uint32_t index = 0;
};

enum class InsertResult { Accepted, LeafFull, OutsideExtent };

struct PointMapState {
  explicit PointMapState(const MappingOptions& o)
      : options(o),
        sampler(GridRect{o.grid_step_px, o.u_min_px, o.u_max_px, o.v_min_px, o.v_max_px}),
        grid(o.octree_resolution_m),
        capacity(static_cast<std::uint32_t>(o.max_points_per_leaf)) {}

  MappingOptions options;
  DepthGridSampler sampler;
  LeafGrid grid;
  std::uint32_t capacity;
  LeafBlocks leaves;           ///< by packed LeafKey; a leaf with count 0 does not exist
  std::size_t leaf_count = 0;  ///< leaves holding points
  std::vector<WorldPoint> points;
  std::vector<std::uint32_t> point_leaf;  ///< leaf of each point (kNone: detached, in update())
  std::vector<std::uint32_t> point_next;  ///< next point of the same leaf (kNone: last)
  std::vector<PointSource> point_src;     ///< origin of each point
  std::size_t untracked_points = 0;       ///< points inserted without a keyframe id
  std::vector<std::uint64_t> ordinal_id;  ///< keyframe id of each ordinal
  std::unordered_map<std::uint64_t, std::uint32_t> ordinal_of;
  /// By ordinal: map slot of each kept point (kNone while a point is out of the map in update()).
  std::vector<std::vector<std::uint32_t>> keyframe_slots;
  CellBlocks cells;  ///< points per cell and the cells changed since the isolated-leaf rule ran
  PointMapStats stats;
  RebuildReport last_rebuild;
  std::uint64_t built_pose_revision = 0;
  std::vector<MapPoint> scratch;  ///< grid samples of the current frame (reused allocation)

  std::uint32_t ordinalOf(std::uint64_t id);
  /// The leaf of p_world (possibly empty); kNone when p_world is beyond the extent.
  std::uint32_t leafAt(const Eigen::Vector3d& p_world);
  /// The leaf of a key if it holds points, or kNone.
  std::uint32_t findLeaf(const LeafKey& key) const;
  void appendPoint(std::uint32_t leaf, const Eigen::Vector3d& p_world, const Rgb& rgb,
                   PointSource src);
  /// Takes point j out of its leaf and out of the map (the last point fills its slot); a leaf
  /// left without points is no leaf any more. j may be detached.
  void removePoint(std::uint32_t j);
  /// Takes point j out of its leaf but keeps its slot (point_leaf kNone: detached), to be
  /// attached again at a corrected position or removed.
  void detachPoint(std::uint32_t j);
  /// Puts the detached point j into `leaf` at p_world.
  void attachPoint(std::uint32_t j, std::uint32_t leaf, const Eigen::Vector3d& p_world);
  CellCoord cellOfLeaf(std::uint32_t leaf) const {
    return LeafKey::unpack(leaves.keyOf(leaf)).cell();
  }
  InsertResult insert(const Eigen::Vector3d& p_world, const Rgb& rgb, PointSource src);
  void clearGeometry();

  /// The isolated-leaf rule where anything changed since it last ran (min_count 0: the rule is
  /// off): removes the isolated cells' leaves and appends their points' origins to `drops`.
  void dropIsolatedLeaves(std::vector<PointSource>& drops, RebuildReport& report);
  /// Removes the dropped points (map points already removed) from their keyframes' kept points
  /// and renumbers the survivors' sources.
  void applyDrops(std::vector<PointSource>& drops, KeyframeStore& store);
  /// End of a rebuild or an update: the isolated-leaf rule, the drops applied, the report
  /// completed (points kept, seconds since `start`) and remembered with the store's revision.
  RebuildReport finishPass(std::vector<PointSource>& drops, KeyframeStore& store,
                           RebuildReport report, std::chrono::steady_clock::time_point start);
};

}  // namespace rgbdi::mapping::detail

namespace rgbdi::mapping {
struct PointMap::Impl : detail::PointMapState {
  using detail::PointMapState::PointMapState;
};
}  // namespace rgbdi::mapping
