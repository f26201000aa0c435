#include "rgbdi/mapping/point_map.h"

#include <chrono>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "mapping/depth_grid_sampler.h"
#include "mapping/point_octree.h"
#include "mapping/pose_check.h"

namespace rgbdi::mapping {
namespace {

struct LeafRecord {
  detail::PointLeafNode* node = nullptr;
  octomap::OcTreeKey key;
  std::uint32_t count = 0;
};

enum class InsertResult { Accepted, LeafFull, OutsideExtent };

}  // namespace

struct PointMap::Impl {
  explicit Impl(const MappingOptions& o)
      : options(o),
        sampler(detail::GridRect{o.grid_step_px, o.u_min_px, o.u_max_px, o.v_min_px, o.v_max_px}),
        tree(o.octree_resolution_m),
        capacity(static_cast<std::uint32_t>(o.max_points_per_leaf)) {}

  MappingOptions options;
  detail::DepthGridSampler sampler;
  detail::PointOctree tree;
  std::uint32_t capacity;
  std::vector<LeafRecord> leaves;
  std::vector<WorldPoint> points;
  std::vector<std::uint32_t> point_leaf;  // leaf record of each point
  PointMapStats stats;
  RebuildReport last_rebuild;
  std::uint64_t built_pose_revision = 0;
  std::vector<MapPoint> scratch;  // grid samples of the current frame (reused allocation)

  InsertResult insert(const Eigen::Vector3d& p_world, const Rgb& rgb) {
    octomap::OcTreeKey key;
    if (!tree.coordToKeyChecked(p_world.x(), p_world.y(), p_world.z(), key))
      return InsertResult::OutsideExtent;
    detail::PointLeafNode* node = tree.touchLeaf(key);
    std::uint32_t leaf = node->getValue();
    if (leaf == detail::kNoLeaf) {
      leaf = static_cast<std::uint32_t>(leaves.size());
      leaves.push_back({node, key, 0});
      node->setValue(leaf);
    }
    LeafRecord& record = leaves[leaf];
    if (record.count >= capacity) return InsertResult::LeafFull;
    ++record.count;
    points.push_back({p_world.cast<float>(), rgb});
    point_leaf.push_back(leaf);
    return InsertResult::Accepted;
  }

  void clearGeometry() {
    tree.clearAll();
    leaves.clear();
    points.clear();
    point_leaf.clear();
  }

  /// Removes isolated leaves: those whose neighbourhood (the 3 x 3 x 3 cells of twice the leaf
  /// size around the leaf's cell, a cube of 6 leaves) holds fewer than `min_count` points.
  /// Returns the surviving-point mask (indexed like `points` before the call) and compacts
  /// points, leaves and node payloads. The neighbourhood is wider than one leaf because a single
  /// keyframe samples a surface more sparsely than the leaf size beyond about 1 m.
  std::vector<char> dropSparseLeaves(std::uint32_t min_count, RebuildReport& report) {
    auto pack = [](int x, int y, int z) {  // cell keys are 3 x 15 bits
      return (static_cast<std::uint64_t>(static_cast<std::uint16_t>(x)) << 32) |
             (static_cast<std::uint64_t>(static_cast<std::uint16_t>(y)) << 16) |
             static_cast<std::uint64_t>(static_cast<std::uint16_t>(z));
    };
    std::unordered_map<std::uint64_t, std::uint32_t> count_in_cell;
    count_in_cell.reserve(leaves.size());
    for (const LeafRecord& l : leaves)
      count_in_cell[pack(l.key[0] >> 1, l.key[1] >> 1, l.key[2] >> 1)] += l.count;
    std::vector<std::uint32_t> new_index(leaves.size(), detail::kNoLeaf);
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
        tree.eraseLeaf(leaves[i].key);
      } else {
        new_index[i] = next++;
      }
    }
    std::vector<LeafRecord> kept_leaves;
    kept_leaves.reserve(next);
    for (std::size_t i = 0; i < leaves.size(); ++i)
      if (new_index[i] != detail::kNoLeaf) {
        leaves[i].node->setValue(new_index[i]);
        kept_leaves.push_back(leaves[i]);
      }
    leaves.swap(kept_leaves);

    std::vector<char> survives(points.size(), 0);
    std::size_t out = 0;
    for (std::size_t j = 0; j < points.size(); ++j) {
      const std::uint32_t leaf = new_index[point_leaf[j]];
      if (leaf == detail::kNoLeaf) continue;
      survives[j] = 1;
      points[out] = points[j];
      point_leaf[out] = leaf;
      ++out;
    }
    points.resize(out);
    point_leaf.resize(out);
    return survives;
  }
};

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
  return insertPoints(m.scratch, T_world_cam);
}

std::vector<MapPoint> PointMap::insertPoints(const std::vector<MapPoint>& points_cam,
                                             const Eigen::Isometry3d& T_world_cam) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument(
        "PointMap::insertPoints: T_world_cam is not a finite rigid transform");
  Impl& m = *impl_;
  ++m.stats.keyframes;
  std::vector<MapPoint> kept;
  kept.reserve(points_cam.size());
  for (const MapPoint& p : points_cam) {
    ++m.stats.candidates;
    switch (m.insert(T_world_cam * p.p_cam.cast<double>(), p.rgb)) {
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
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      const MapPoint& p = kf.points[i];
      switch (m.insert(kf.T_world_cam * p.p_cam.cast<double>(), p.rgb)) {
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
         m.point_leaf.capacity() * sizeof(std::uint32_t) + m.scratch.capacity() * sizeof(MapPoint);
}

}  // namespace rgbdi::mapping
