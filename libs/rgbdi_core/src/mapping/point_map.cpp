#include "rgbdi/mapping/point_map.h"

#include <chrono>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "mapping/depth_grid_sampler.h"
#include "mapping/point_map_impl.h"
#include "mapping/point_octree.h"
#include "mapping/pose_check.h"

namespace rgbdi::mapping {
namespace detail {

std::vector<char> PointMapState::dropSparseLeaves(std::uint32_t min_count, RebuildReport& report) {
  std::unordered_map<std::uint64_t, std::uint32_t> count_in_cell;
  count_in_cell.reserve(leaves.size());
  for (const LeafRecord& l : leaves) count_in_cell[cellOf(l.key)] += l.count;
  auto pack = [](int x, int y, int z) {  // as cellOf, for neighbour cells
    return (static_cast<std::uint64_t>(static_cast<std::uint16_t>(x)) << 32) |
           (static_cast<std::uint64_t>(static_cast<std::uint16_t>(y)) << 16) |
           static_cast<std::uint64_t>(static_cast<std::uint16_t>(z));
  };
  std::vector<std::uint32_t> new_index(leaves.size(), kNoLeaf);
  std::vector<std::uint64_t> dropped_cells;
  std::uint32_t next = 0;
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const int cx = leaves[i].key[0] >> 1, cy = leaves[i].key[1] >> 1, cz = leaves[i].key[2] >> 1;
    std::uint32_t n = 0;
    for (int dx = -1; dx <= 1 && n < min_count; ++dx)
      for (int dy = -1; dy <= 1 && n < min_count; ++dy)
        for (int dz = -1; dz <= 1 && n < min_count; ++dz) {
          const auto it = count_in_cell.find(pack(cx + dx, cy + dy, cz + dz));
          if (it != count_in_cell.end()) n += it->second;
        }
    if (n < min_count) {
      ++report.sparse_leaves_removed;
      report.sparse_points_removed += leaves[i].count;
      cells.add(cellOf(leaves[i].key), -static_cast<std::int64_t>(leaves[i].count));
      dropped_cells.push_back(cellOf(leaves[i].key));
      tree.eraseLeaf(leaves[i].key);
    } else {
      new_index[i] = next++;
    }
  }
  std::vector<LeafRecord> kept_leaves;
  kept_leaves.reserve(next);
  for (std::size_t i = 0; i < leaves.size(); ++i)
    if (new_index[i] != kNoLeaf) {
      leaves[i].node->setValue(new_index[i]);
      kept_leaves.push_back(leaves[i]);
    }
  leaves.swap(kept_leaves);
  // The drops change their neighbours' counts: the next pass looks there again.
  dirty_cells.swap(dropped_cells);
  ++pass;  // every leaf is clean

  std::vector<char> survives(points.size(), 0);
  std::size_t out = 0;
  for (std::size_t j = 0; j < points.size(); ++j) {
    const std::uint32_t leaf = new_index[point_leaf[j]];
    if (leaf == kNoLeaf) continue;
    survives[j] = 1;
    points[out] = points[j];
    point_leaf[out] = leaf;
    point_src[out] = point_src[j];
    ++out;
  }
  points.resize(out);
  point_leaf.resize(out);
  point_src.resize(out);
  return survives;
}

}  // namespace detail

using detail::InsertResult;
using detail::LeafRecord;
using detail::PointSource;

PointMap::PointMap(const MappingOptions& options) {
  options.validate();
  impl_ = std::make_unique<Impl>(options);
}

PointMap::~PointMap() = default;
PointMap::PointMap(PointMap&&) noexcept = default;
PointMap& PointMap::operator=(PointMap&&) noexcept = default;

const MappingOptions& PointMap::options() const { return impl_->options; }

std::vector<MapPoint> PointMap::insertKeyframe(const RgbdFrame& frame,
                                               const Eigen::Isometry3d& T_world_cam) {
  return insertKeyframe(frame, T_world_cam, kUntrackedKeyframe);
}

std::vector<MapPoint> PointMap::insertKeyframe(const RgbdFrame& frame,
                                               const Eigen::Isometry3d& T_world_cam,
                                               std::uint64_t keyframe_id) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument("PointMap::insertKeyframe: " + detail::frameLabel(frame) +
                                ": T_world_cam is not a finite rigid transform");
  Impl& m = *impl_;
  detail::GridSampleCounts counts;
  m.scratch.clear();
  m.sampler.sample(frame, 1, m.options.depth_min_m, m.options.depth_max_m, m.scratch, counts);
  m.stats.grid_points += counts.grid_points;
  m.stats.no_depth += counts.no_depth;
  m.stats.out_of_range += counts.out_of_range;
  return insertPoints(m.scratch, T_world_cam, keyframe_id);
}

std::vector<MapPoint> PointMap::insertPoints(const std::vector<MapPoint>& points_cam,
                                             const Eigen::Isometry3d& T_world_cam,
                                             std::uint64_t keyframe_id) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument(
        "PointMap::insertPoints: T_world_cam is not a finite rigid transform");
  Impl& m = *impl_;
  const std::uint32_t ordinal =
      keyframe_id == kUntrackedKeyframe ? detail::kNone : m.ordinalOf(keyframe_id);
  ++m.stats.keyframes;
  std::vector<MapPoint> kept;
  kept.reserve(points_cam.size());
  for (const MapPoint& p : points_cam) {
    ++m.stats.candidates;
    const PointSource src{ordinal, static_cast<std::uint32_t>(kept.size())};
    switch (m.insert(T_world_cam * p.p_cam.cast<double>(), p.rgb, src)) {
      case InsertResult::Accepted:
        ++m.stats.accepted;
        kept.push_back(p);
        break;
      case InsertResult::LeafFull:
        ++m.stats.rejected_full_leaf;
        break;
      case InsertResult::OutsideExtent:
        ++m.stats.outside_extent;
        break;
    }
  }
  return kept;
}

RebuildReport PointMap::rebuild(KeyframeStore& store) {
  const auto start = std::chrono::steady_clock::now();
  Impl& m = *impl_;
  RebuildReport report;
  report.keyframes = store.size();
  m.clearGeometry();

  // Where each map point came from, to remove dropped points from their keyframes.
  struct Source {
    std::uint32_t slot, index;
  };
  std::vector<Source> sources;
  sources.reserve(store.pointCount());
  std::vector<std::vector<char>> keep(store.size());
  m.points.reserve(store.pointCount());
  m.point_leaf.reserve(store.pointCount());
  for (std::size_t slot = 0; slot < store.size(); ++slot) {
    const Keyframe& kf = store.at(slot);
    keep[slot].assign(kf.points.size(), 0);
    report.input_points += kf.points.size();
    const std::uint32_t ordinal = m.ordinalOf(kf.id);
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      const MapPoint& p = kf.points[i];
      const PointSource src{ordinal, static_cast<std::uint32_t>(i)};
      switch (m.insert(kf.T_world_cam * p.p_cam.cast<double>(), p.rgb, src)) {
        case InsertResult::Accepted:
          sources.push_back({static_cast<std::uint32_t>(slot), static_cast<std::uint32_t>(i)});
          break;
        case InsertResult::LeafFull:
          ++report.rejected_full_leaf;
          break;
        case InsertResult::OutsideExtent:
          ++report.outside_extent;
          break;
      }
    }
  }

  const std::vector<char> survives =
      m.dropSparseLeaves(static_cast<std::uint32_t>(m.options.min_points_per_leaf_rebuild), report);
  for (std::size_t j = 0; j < sources.size(); ++j)
    if (survives[j]) keep[sources[j].slot][sources[j].index] = 1;

  for (std::size_t slot = 0; slot < store.size(); ++slot) {
    const std::vector<MapPoint>& old_points = store.at(slot).points;
    std::vector<MapPoint> kept;
    kept.reserve(old_points.size());
    for (std::size_t i = 0; i < old_points.size(); ++i)
      if (keep[slot][i]) kept.push_back(old_points[i]);
    if (kept.size() != old_points.size()) store.replacePoints(slot, std::move(kept));
  }
  // The map holds its points in (keyframe, index) order: a point's index in its keyframe's
  // compacted list is the count of that keyframe's points before it.
  std::vector<std::uint32_t> next_index(m.ordinal_id.size(), 0);
  for (PointSource& src : m.point_src) src.index = next_index[src.ordinal]++;

  report.kept_points = m.points.size();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  m.last_rebuild = report;
  m.built_pose_revision = store.poseRevision();
  return report;
}

bool PointMap::isOutdated(const KeyframeStore& store) const {
  return store.poseRevision() != impl_->built_pose_revision;
}

void PointMap::clear() {
  impl_->clearGeometry();
  impl_->ordinal_id.clear();
  impl_->ordinal_of.clear();
  impl_->stats = PointMapStats{};
  impl_->last_rebuild = RebuildReport{};
}

std::size_t PointMap::pointCount() const { return impl_->points.size(); }
std::size_t PointMap::leafCount() const { return impl_->leaves.size(); }
const std::vector<WorldPoint>& PointMap::points() const { return impl_->points; }
const PointMapStats& PointMap::stats() const { return impl_->stats; }
const RebuildReport& PointMap::lastRebuild() const { return impl_->last_rebuild; }

std::size_t PointMap::pointsInLeafAt(const Eigen::Vector3d& p_world) const {
  octomap::OcTreeKey key;
  if (!impl_->tree.coordToKeyChecked(p_world.x(), p_world.y(), p_world.z(), key)) return 0;
  const detail::PointLeafNode* node = impl_->tree.search(key);
  if (node == nullptr || node->getValue() == detail::kNoLeaf) return 0;
  return impl_->leaves[node->getValue()].count;
}

Eigen::Vector3d PointMap::leafCenterAt(const Eigen::Vector3d& p_world) const {
  const octomap::OcTreeKey key = impl_->tree.coordToKey(p_world.x(), p_world.y(), p_world.z());
  const octomap::point3d c = impl_->tree.keyToCoord(key);
  return {c.x(), c.y(), c.z()};
}

std::size_t PointMap::memoryBytes() const {
  const Impl& m = *impl_;
  return sizeof(PointMap) + sizeof(Impl) + m.tree.nodeBytes(m.leaves.size()) +
         m.leaves.capacity() * sizeof(LeafRecord) + m.points.capacity() * sizeof(WorldPoint) +
         m.point_leaf.capacity() * sizeof(std::uint32_t) +
         m.point_src.capacity() * sizeof(PointSource) + m.scratch.capacity() * sizeof(MapPoint) +
         m.ordinal_id.capacity() * sizeof(std::uint64_t) +
         m.ordinal_of.size() * (sizeof(std::uint64_t) + sizeof(std::uint32_t) + 2 * sizeof(void*)) +
         m.dirty_cells.capacity() * sizeof(std::uint64_t) + m.cells.bytes();
}

}  // namespace rgbdi::mapping
