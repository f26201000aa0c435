#include "rgbdi/mapping/point_map.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "mapping/depth_grid_sampler.h"
#include "mapping/point_map_impl.h"
#include "mapping/pose_check.h"

namespace rgbdi::mapping {
namespace detail {

std::uint32_t PointMapState::ordinalOf(std::uint64_t id) {
  const auto [it, added] = ordinal_of.emplace(id, static_cast<std::uint32_t>(ordinal_id.size()));
  if (added) {
    ordinal_id.push_back(id);
    keyframe_slots.emplace_back();
  }
  return it->second;
}

std::uint32_t PointMapState::leafAt(const Eigen::Vector3d& p_world) {
  LeafKey key;
  if (!grid.keyOf(p_world, key)) return kNone;
  return leaves.touch(key.packed());
}

std::uint32_t PointMapState::findLeaf(const LeafKey& key) const {
  return leaves.find(key.packed());
}

void PointMapState::appendPoint(std::uint32_t leaf, const Eigen::Vector3d& p_world, const Rgb& rgb,
                                PointSource src) {
  const auto j = static_cast<std::uint32_t>(points.size());
  LeafBlocks::Leaf& l = leaves[leaf];
  if (l.count++ == 0) ++leaf_count;
  cells.add(cellOfLeaf(leaf), 1);
  points.push_back({p_world.cast<float>(), rgb});
  point_leaf.push_back(leaf);
  point_next.push_back(l.head);
  l.head = j;
  point_src.push_back(src);
  if (src.ordinal == kNone) {
    ++untracked_points;
    return;
  }
  std::vector<std::uint32_t>& slots = keyframe_slots[src.ordinal];
  if (src.index >= slots.size()) slots.resize(src.index + 1, kNone);
  slots[src.index] = j;
}

void PointMapState::detachPoint(std::uint32_t j) {
  // Unlink j from its leaf (lists hold at most max_points_per_leaf points).
  const std::uint32_t leaf = point_leaf[j];
  LeafBlocks::Leaf& l = leaves[leaf];
  std::uint32_t* link = &l.head;
  while (*link != j) link = &point_next[*link];
  *link = point_next[j];
  if (--l.count == 0) --leaf_count;
  cells.add(cellOfLeaf(leaf), -1);
  point_leaf[j] = kNone;
}

void PointMapState::attachPoint(std::uint32_t j, std::uint32_t leaf,
                                const Eigen::Vector3d& p_world) {
  LeafBlocks::Leaf& l = leaves[leaf];
  if (l.count++ == 0) ++leaf_count;
  cells.add(cellOfLeaf(leaf), 1);
  points[j].p_world = p_world.cast<float>();
  point_leaf[j] = leaf;
  point_next[j] = l.head;
  l.head = j;
}

void PointMapState::removePoint(std::uint32_t j) {
  if (point_leaf[j] != kNone) detachPoint(j);
  const PointSource src = point_src[j];
  if (src.ordinal == kNone)
    --untracked_points;
  else
    keyframe_slots[src.ordinal][src.index] = kNone;
  // The last point fills the slot: relink it (unless detached) and tell its keyframe.
  const auto last = static_cast<std::uint32_t>(points.size() - 1);
  if (last != j) {
    if (point_leaf[last] != kNone) {
      std::uint32_t* link = &leaves[point_leaf[last]].head;
      while (*link != last) link = &point_next[*link];
      *link = j;
    }
    points[j] = points[last];
    point_leaf[j] = point_leaf[last];
    point_next[j] = point_next[last];
    point_src[j] = point_src[last];
    if (point_src[j].ordinal != kNone) keyframe_slots[point_src[j].ordinal][point_src[j].index] = j;
  }
  points.pop_back();
  point_leaf.pop_back();
  point_next.pop_back();
  point_src.pop_back();
}

InsertResult PointMapState::insert(const Eigen::Vector3d& p_world, const Rgb& rgb,
                                   PointSource src) {
  const std::uint32_t leaf = leafAt(p_world);
  if (leaf == kNone) return InsertResult::OutsideExtent;
  if (leaves[leaf].count >= capacity) return InsertResult::LeafFull;
  appendPoint(leaf, p_world, rgb, src);
  return InsertResult::Accepted;
}

void PointMapState::clearGeometry() {
  leaves.clear();
  leaf_count = 0;
  points.clear();
  point_leaf.clear();
  point_next.clear();
  point_src.clear();
  untracked_points = 0;
  for (std::vector<std::uint32_t>& slots : keyframe_slots) slots.clear();
  cells.clear();
}

void PointMapState::dropIsolatedLeaves(std::vector<PointSource>& drops, RebuildReport& report) {
  const auto min_count = static_cast<std::uint32_t>(options.min_points_per_leaf_rebuild);
  if (min_count == 0) {
    cells.discardChanges();
    return;
  }
  // Every verdict is taken on the map before any drop of this pass (as a rebuild does); the
  // drops mark their cells changed, so the next pass looks at their neighbours again.
  for (const CellCoord& c : cells.takeIsolatedCells(min_count))
    for (int i = 0; i < 8; ++i) {  // the cell's leaves
      LeafKey key;
      key.k[0] = static_cast<std::uint16_t>(2 * c.x + (i & 1));
      key.k[1] = static_cast<std::uint16_t>(2 * c.y + ((i >> 1) & 1));
      key.k[2] = static_cast<std::uint16_t>(2 * c.z + ((i >> 2) & 1));
      const std::uint32_t leaf = findLeaf(key);
      if (leaf == kNone) continue;
      ++report.sparse_leaves_removed;
      report.sparse_points_removed += leaves[leaf].count;
      while (leaves[leaf].head != kNone) {
        const std::uint32_t j = leaves[leaf].head;
        drops.push_back(point_src[j]);
        removePoint(j);
      }
    }
}

RebuildReport PointMapState::finishPass(std::vector<PointSource>& drops, KeyframeStore& store,
                                        RebuildReport report,
                                        std::chrono::steady_clock::time_point start) {
  dropIsolatedLeaves(drops, report);
  applyDrops(drops, store);
  report.kept_points = points.size();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  last_rebuild = report;
  built_pose_revision = store.poseRevision();
  return report;
}

void PointMapState::applyDrops(std::vector<PointSource>& drops, KeyframeStore& store) {
  std::sort(drops.begin(), drops.end(), [](PointSource a, PointSource b) {
    return a.ordinal < b.ordinal || (a.ordinal == b.ordinal && a.index < b.index);
  });
  for (std::size_t d = 0; d < drops.size();) {
    const std::uint32_t o = drops[d].ordinal;
    const Keyframe& kf = store.get(ordinal_id[o]);
    const std::size_t slot = static_cast<std::size_t>(&kf - store.keyframes().data());
    std::vector<std::uint32_t>& slots = keyframe_slots[o];
    std::size_t group_end = d;
    while (group_end < drops.size() && drops[group_end].ordinal == o) ++group_end;
    std::vector<MapPoint> kept;
    kept.reserve(kf.points.size() - (group_end - d));
    std::size_t out = 0;
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      if (d < drops.size() && drops[d].ordinal == o && drops[d].index == i) {
        ++d;
        continue;
      }
      const std::uint32_t j = slots[i];
      point_src[j].index = static_cast<std::uint32_t>(out);
      slots[out++] = j;
      kept.push_back(kf.points[i]);
    }
    slots.resize(out);
    store.replacePoints(slot, std::move(kept));
  }
  drops.clear();
}

}  // namespace detail

using detail::InsertResult;
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
  const std::size_t n = store.pointCount();
  m.points.reserve(n);
  m.point_leaf.reserve(n);
  m.point_next.reserve(n);
  m.point_src.reserve(n);
  // Every keyframe's kept points in id order; those that no longer fit leave their keyframes.
  std::vector<PointSource> drops;
  for (std::size_t slot = 0; slot < store.size(); ++slot) {
    const Keyframe& kf = store.at(slot);
    report.input_points += kf.points.size();
    const std::uint32_t ordinal = m.ordinalOf(kf.id);
    m.keyframe_slots[ordinal].reserve(kf.points.size());
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      const MapPoint& p = kf.points[i];
      const PointSource src{ordinal, static_cast<std::uint32_t>(i)};
      switch (m.insert(kf.T_world_cam * p.p_cam.cast<double>(), p.rgb, src)) {
        case InsertResult::Accepted:
          break;
        case InsertResult::LeafFull:
          ++report.rejected_full_leaf;
          drops.push_back(src);
          break;
        case InsertResult::OutsideExtent:
          ++report.outside_extent;
          drops.push_back(src);
          break;
      }
    }
    // A rejected last point leaves the slot list short: pad it (applyDrops renumbers).
    m.keyframe_slots[ordinal].resize(kf.points.size(), detail::kNone);
  }
  // Every cell changed: the isolated-leaf rule looks at the whole map.
  return m.finishPass(drops, store, report, start);
}

bool PointMap::isOutdated(const KeyframeStore& store) const {
  return store.poseRevision() != impl_->built_pose_revision;
}

void PointMap::clear() {
  impl_->clearGeometry();
  impl_->ordinal_id.clear();
  impl_->ordinal_of.clear();
  impl_->keyframe_slots.clear();
  impl_->stats = PointMapStats{};
  impl_->last_rebuild = RebuildReport{};
}

std::size_t PointMap::pointCount() const { return impl_->points.size(); }
std::size_t PointMap::leafCount() const { return impl_->leaf_count; }
const std::vector<WorldPoint>& PointMap::points() const { return impl_->points; }
const PointMapStats& PointMap::stats() const { return impl_->stats; }
const RebuildReport& PointMap::lastRebuild() const { return impl_->last_rebuild; }

std::size_t PointMap::pointsInLeafAt(const Eigen::Vector3d& p_world) const {
  detail::LeafKey key;
  if (!impl_->grid.keyOf(p_world, key)) return 0;
  const std::uint32_t leaf = impl_->findLeaf(key);
  return leaf == detail::kNone ? 0 : impl_->leaves[leaf].count;
}

Eigen::Vector3d PointMap::leafCenterAt(const Eigen::Vector3d& p_world) const {
  detail::LeafKey key;
  if (!impl_->grid.keyOf(p_world, key))
    throw std::invalid_argument("PointMap::leafCenterAt: the point is beyond the map's extent");
  return impl_->grid.centre(key);
}

std::size_t PointMap::memoryBytes() const {
  const Impl& m = *impl_;
  std::size_t slots = m.keyframe_slots.capacity() * sizeof(std::vector<std::uint32_t>);
  for (const std::vector<std::uint32_t>& s : m.keyframe_slots)
    slots += s.capacity() * sizeof(std::uint32_t);
  return sizeof(PointMap) + sizeof(Impl) + m.leaves.bytes() +
         m.points.capacity() * sizeof(WorldPoint) +
         m.point_leaf.capacity() * sizeof(std::uint32_t) +
         m.point_next.capacity() * sizeof(std::uint32_t) +
         m.point_src.capacity() * sizeof(PointSource) + m.scratch.capacity() * sizeof(MapPoint) +
         m.ordinal_id.capacity() * sizeof(std::uint64_t) +
         m.ordinal_of.size() * (sizeof(std::uint64_t) + sizeof(std::uint32_t) + 2 * sizeof(void*)) +
         slots + m.cells.bytes();
}

}  // namespace rgbdi::mapping
