// PointMap's state, shared by the insertion/rebuild code (point_map.cpp) and the incremental
// update after a loop (point_map_update.cpp). Internal to the mapping stage.
//
// Besides the octree and the flat point arrays, the map remembers where each point came from
// (keyframe and index in its kept points) and which 2 x 2 x 2-leaf cells changed since the
// isolated-leaf rule was last applied: that is what lets update() touch only what moved and still
// give exactly what rebuild() gives.
#pragma once

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "mapping/cell_count_table.h"
#include "mapping/depth_grid_sampler.h"
#include "mapping/point_octree.h"
#include "rgbdi/mapping/map_point.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/point_map.h"

namespace rgbdi::mapping::detail {

inline constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct LeafRecord {
  PointLeafNode* node = nullptr;
  octomap::OcTreeKey key;
  std::uint32_t count = 0;
  /// == PointMapState::pass: points added or removed since the isolated-leaf rule last ran
  std::uint32_t dirty_pass = 0;
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
        tree(o.octree_resolution_m),
        capacity(static_cast<std::uint32_t>(o.max_points_per_leaf)) {}

  MappingOptions options;
  DepthGridSampler sampler;
  PointOctree tree;
  std::uint32_t capacity;
  std::vector<LeafRecord> leaves;
  std::vector<WorldPoint> points;
  std::vector<std::uint32_t> point_leaf;  ///< leaf record of each point
  std::vector<PointSource> point_src;     ///< origin of each point
  std::size_t untracked_points = 0;       ///< points inserted without a keyframe id
  std::vector<std::uint64_t> ordinal_id;  ///< keyframe id of each ordinal
  std::unordered_map<std::uint64_t, std::uint32_t> ordinal_of;
  /// Cells (packed, see cellOf) where points were added or removed, or leaves dropped, since the
  /// isolated-leaf rule last ran; may hold duplicates.
  std::vector<std::uint64_t> dirty_cells;
  std::uint32_t pass = 1;  ///< number of the next pass of the isolated-leaf rule
  CellCountTable cells;    ///< points per cell, kept up to date
  PointMapStats stats;
  RebuildReport last_rebuild;
  std::uint64_t built_pose_revision = 0;
  std::vector<MapPoint> scratch;  ///< grid samples of the current frame (reused allocation)

  /// A cell is 2 x 2 x 2 leaves: the leaf key halved, three 16-bit fields.
  static std::uint64_t cellOf(const octomap::OcTreeKey& k) {
    return (static_cast<std::uint64_t>(k[0] >> 1) << 32) |
           (static_cast<std::uint64_t>(k[1] >> 1) << 16) | static_cast<std::uint64_t>(k[2] >> 1);
  }

  std::uint32_t ordinalOf(std::uint64_t id) {
    const auto [it, added] = ordinal_of.emplace(id, static_cast<std::uint32_t>(ordinal_id.size()));
    if (added) ordinal_id.push_back(id);
    return it->second;
  }

  void markDirty(std::uint32_t leaf) {
    LeafRecord& l = leaves[leaf];
    if (l.dirty_pass == pass) return;
    l.dirty_pass = pass;
    dirty_cells.push_back(cellOf(l.key));
  }

  /// Takes `n` points off the leaf's count (the caller removes the points themselves).
  void removeCounts(std::uint32_t leaf, std::uint32_t n) {
    leaves[leaf].count -= n;
    cells.add(cellOf(leaves[leaf].key), -static_cast<std::int64_t>(n));
  }

  /// Finds or creates the leaf of p_world; kNone when p_world is beyond the octree's extent.
  std::uint32_t leafAt(const Eigen::Vector3d& p_world) {
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(p_world.x(), p_world.y(), p_world.z(), key)) return kNone;
    PointLeafNode* node = tree.touchLeaf(key);
    std::uint32_t leaf = node->getValue();
    if (leaf == kNoLeaf) {
      leaf = static_cast<std::uint32_t>(leaves.size());
      leaves.push_back({node, key, 0, 0});
      node->setValue(leaf);
    }
    return leaf;
  }

  void appendPoint(std::uint32_t leaf, const Eigen::Vector3d& p_world, const Rgb& rgb,
                   PointSource src) {
    ++leaves[leaf].count;
    cells.add(cellOf(leaves[leaf].key), 1);
    points.push_back({p_world.cast<float>(), rgb});
    point_leaf.push_back(leaf);
    point_src.push_back(src);
    if (src.ordinal == kNone) ++untracked_points;
    markDirty(leaf);
  }

  InsertResult insert(const Eigen::Vector3d& p_world, const Rgb& rgb, PointSource src) {
    const std::uint32_t leaf = leafAt(p_world);
    if (leaf == kNone) return InsertResult::OutsideExtent;
    if (leaves[leaf].count >= capacity) return InsertResult::LeafFull;
    appendPoint(leaf, p_world, rgb, src);
    return InsertResult::Accepted;
  }

  void clearGeometry() {
    tree.clearAll();
    leaves.clear();
    points.clear();
    point_leaf.clear();
    point_src.clear();
    untracked_points = 0;
    dirty_cells.clear();
    cells.clear();
  }

  /// The isolated-leaf rule over every leaf (rebuild()): drops the leaves whose neighbourhood
  /// (the 3 x 3 x 3 cells around the leaf's cell, a cube of 6 leaves) holds fewer than
  /// `min_count` points. Returns the surviving-point mask (indexed like `points` before the
  /// call) and compacts points, leaves and node payloads. The neighbourhood is wider than one
  /// leaf because a single keyframe samples a surface more sparsely than the leaf size beyond
  /// about 1 m. Afterwards the dropped leaves' cells are the only dirty ones.
  std::vector<char> dropSparseLeaves(std::uint32_t min_count, RebuildReport& report);
};

}  // namespace rgbdi::mapping::detail

namespace rgbdi::mapping {
struct PointMap::Impl : detail::PointMapState {
  using detail::PointMapState::PointMapState;
};
}  // namespace rgbdi::mapping
