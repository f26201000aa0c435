// PointMap::update: the map after a loop correction, touching only the keyframes that moved,
// equal to PointMap::rebuild on the same store (see point_map.h for the rules it reproduces).
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "mapping/cell_count_table.h"
#include "mapping/point_map_impl.h"
#include "rgbdi/mapping/point_map.h"

namespace rgbdi::mapping {
namespace {

using detail::CellCountTable;
using detail::kNone;
using detail::LeafRecord;
using detail::PointMapState;
using detail::PointSource;

/// Per-leaf lists of live points (built once per update; dead entries are skipped).
struct LeafLists {
  std::vector<std::uint32_t> head;  ///< by leaf record
  std::vector<std::uint32_t> next;  ///< by point
  std::vector<char> dead;           ///< by point: left the map during this update
};

/// Splits a packed cell (PointMapState::cellOf) into its coordinates.
void unpack(std::uint64_t cell, int& cx, int& cy, int& cz) {
  cx = static_cast<int>((cell >> 32) & 0xffff);
  cy = static_cast<int>((cell >> 16) & 0xffff);
  cz = static_cast<int>(cell & 0xffff);
}

std::uint64_t pack(int cx, int cy, int cz) {
  return (static_cast<std::uint64_t>(static_cast<std::uint16_t>(cx)) << 32) |
         (static_cast<std::uint64_t>(static_cast<std::uint16_t>(cy)) << 16) |
         static_cast<std::uint64_t>(static_cast<std::uint16_t>(cz));
}

/// The isolated-leaf rule where it can have changed: every cell within one cell of a dirty
/// cell is evaluated once (its 3 x 3 x 3 neighbourhood count against min_count, on the map as
/// it is before any drop of this pass, as rebuild() does), or every cell when most are dirty.
/// Returns the cells whose leaves must go.
std::vector<std::uint64_t> isolatedCells(PointMapState& m, std::uint32_t min_count) {
  std::vector<std::uint64_t> isolated;
  CellCountTable& table = m.cells;
  const std::uint32_t stamp = m.pass;
  auto evaluate = [&](CellCountTable::Entry& e) {
    e.stamp = stamp;
    std::uint32_t n = e.count;  // its own cell first: usually enough
    if (n >= min_count) return;
    int cx, cy, cz;
    unpack(e.cell, cx, cy, cz);
    for (int dx = -1; dx <= 1 && n < min_count; ++dx)
      for (int dy = -1; dy <= 1 && n < min_count; ++dy)
        for (int dz = -1; dz <= 1 && n < min_count; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          if (const CellCountTable::Entry* nb = table.find(pack(cx + dx, cy + dy, cz + dz)))
            n += nb->count;
        }
    if (n < min_count) isolated.push_back(e.cell);
  };
  std::vector<std::uint64_t>& dirty = m.dirty_cells;
  std::sort(dirty.begin(), dirty.end());
  dirty.erase(std::unique(dirty.begin(), dirty.end()), dirty.end());
  // Dilating a dirty cell costs 27 look-ups, evaluating a cell 1 to 27 (about 8 on a map of
  // single-keyframe surfaces); the table holds slots / 4 to slots / 2 cells.
  if (dirty.size() * 27 > table.slots().size() * 2) {
    for (CellCountTable::Entry& e : table.slots())
      if (e.cell != CellCountTable::kEmpty && e.count > 0) evaluate(e);
    return isolated;
  }
  for (std::uint64_t cell : dirty) {
    int cx, cy, cz;
    unpack(cell, cx, cy, cz);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          CellCountTable::Entry* e = table.find(pack(cx + dx, cy + dy, cz + dz));
          if (e != nullptr && e->stamp != stamp) evaluate(*e);
        }
  }
  return isolated;
}

}  // namespace

RebuildReport PointMap::update(KeyframeStore& store, const std::vector<std::uint64_t>& moved_ids) {
  const auto start = std::chrono::steady_clock::now();
  PointMapState& m = *impl_;
  if (m.untracked_points > 0)
    throw std::logic_error("PointMap::update: " + std::to_string(m.untracked_points) +
                           " points were inserted without a keyframe id (use rebuild)");
  RebuildReport report;
  report.keyframes = store.size();
  report.input_points = store.pointCount();

  // Keyframes: store slot and moved flag by ordinal; moved ones in id order (rebuild's order).
  const std::size_t n_ord = m.ordinal_id.size();
  std::vector<std::uint32_t> slot_of(n_ord, kNone);
  for (std::size_t slot = 0; slot < store.size(); ++slot) {
    const auto it = m.ordinal_of.find(store.at(slot).id);
    if (it != m.ordinal_of.end()) slot_of[it->second] = static_cast<std::uint32_t>(slot);
  }
  std::vector<char> moved(n_ord, 0);
  std::vector<std::uint32_t> moved_list;
  for (std::uint64_t id : moved_ids) {
    if (!store.contains(id))
      throw std::invalid_argument("PointMap::update: moved keyframe " + std::to_string(id) +
                                  " is not in the store");
    const auto it = m.ordinal_of.find(id);
    if (it == m.ordinal_of.end()) {
      if (!store.get(id).points.empty())
        throw std::logic_error("PointMap::update: keyframe " + std::to_string(id) +
                               " has kept points the map did not insert");
      continue;
    }
    if (!moved[it->second]) moved_list.push_back(it->second);
    moved[it->second] = 1;
  }
  std::sort(moved_list.begin(), moved_list.end(),
            [&](std::uint32_t a, std::uint32_t b) { return m.ordinal_id[a] < m.ordinal_id[b]; });

  // 1. The moved keyframes' points leave their leaves; the others are listed per leaf.
  const std::size_t n0 = m.points.size();
  LeafLists lists;
  lists.head.assign(m.leaves.size(), kNone);
  lists.next.resize(n0);
  lists.dead.assign(n0, 0);
  std::vector<std::uint32_t> held(n_ord, 0);  // map points per ordinal
  for (std::size_t j = 0; j < n0; ++j) {
    const PointSource s = m.point_src[j];
    if (slot_of[s.ordinal] == kNone)
      throw std::logic_error("PointMap::update: the map holds points of keyframe " +
                             std::to_string(m.ordinal_id[s.ordinal]) +
                             ", which is not in the store");
    ++held[s.ordinal];
    const std::uint32_t leaf = m.point_leaf[j];
    if (moved[s.ordinal]) {
      lists.dead[j] = 1;
      m.removeCounts(leaf, 1);
      m.markDirty(leaf);
    } else {
      lists.next[j] = lists.head[leaf];
      lists.head[leaf] = static_cast<std::uint32_t>(j);
    }
  }
  for (std::uint32_t o : moved_list)
    if (held[o] != store.at(slot_of[o]).points.size())
      throw std::logic_error("PointMap::update: keyframe " + std::to_string(m.ordinal_id[o]) +
                             " keeps " + std::to_string(store.at(slot_of[o]).points.size()) +
                             " points, the map holds " + std::to_string(held[o]));

  // 2. Re-insert them at their new poses. A full leaf keeps the points that come first in
  // (id, index) order: the arriving point replaces the leaf's last one if it comes before it.
  auto before = [&](PointSource a, PointSource b) {
    const std::uint64_t ia = m.ordinal_id[a.ordinal], ib = m.ordinal_id[b.ordinal];
    return ia < ib || (ia == ib && a.index < b.index);
  };
  std::vector<PointSource> drops;  // kept points that leave the map
  for (std::uint32_t o : moved_list) {
    const Keyframe& kf = store.at(slot_of[o]);
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      const MapPoint& p = kf.points[i];
      const PointSource src{o, static_cast<std::uint32_t>(i)};
      const Eigen::Vector3d p_world = kf.T_world_cam * p.p_cam.cast<double>();
      const std::uint32_t leaf = m.leafAt(p_world);
      if (leaf == kNone) {
        ++report.outside_extent;
        drops.push_back(src);
        continue;
      }
      if (leaf >= lists.head.size()) lists.head.resize(leaf + 1, kNone);
      if (m.leaves[leaf].count >= m.capacity) {
        std::uint32_t last = kNone;
        for (std::uint32_t j = lists.head[leaf]; j != kNone; j = lists.next[j])
          if (!lists.dead[j] && (last == kNone || before(m.point_src[last], m.point_src[j])))
            last = j;
        ++report.rejected_full_leaf;
        if (last == kNone || !before(src, m.point_src[last])) {
          drops.push_back(src);
          continue;
        }
        lists.dead[last] = 1;
        drops.push_back(m.point_src[last]);
        m.removeCounts(leaf, 1);
      }
      lists.next.push_back(lists.head[leaf]);
      lists.head[leaf] = static_cast<std::uint32_t>(m.points.size());
      lists.dead.push_back(0);
      m.appendPoint(leaf, p_world, p.rgb, src);
    }
  }

  // 3. Leaves left empty go (rebuild() would not create them); their cells are dirty.
  std::vector<char> removed(m.leaves.size(), 0);
  std::vector<octomap::OcTreeKey> erase_keys;
  for (std::size_t l = 0; l < m.leaves.size(); ++l)
    if (m.leaves[l].count == 0) {
      removed[l] = 1;
      erase_keys.push_back(m.leaves[l].key);
      m.dirty_cells.push_back(PointMapState::cellOf(m.leaves[l].key));
    }
  for (const octomap::OcTreeKey& k : erase_keys) m.tree.eraseLeaf(k);
  erase_keys.clear();

  // 4. The isolated-leaf rule where anything changed since it last ran.
  const auto min_count = static_cast<std::uint32_t>(m.options.min_points_per_leaf_rebuild);
  std::vector<std::uint64_t> isolated;
  if (min_count > 0) isolated = isolatedCells(m, min_count);
  ++m.pass;  // every leaf is clean
  m.dirty_cells.clear();
  for (std::uint64_t cell : isolated) {
    int cx, cy, cz;
    unpack(cell, cx, cy, cz);
    for (int i = 0; i < 8; ++i) {  // the cell's leaves
      const octomap::OcTreeKey key(static_cast<octomap::key_type>(2 * cx + (i & 1)),
                                   static_cast<octomap::key_type>(2 * cy + ((i >> 1) & 1)),
                                   static_cast<octomap::key_type>(2 * cz + ((i >> 2) & 1)));
      const detail::PointLeafNode* node = m.tree.search(key);
      if (node == nullptr || node->getValue() >= m.leaves.size()) continue;
      const std::uint32_t leaf = node->getValue();
      LeafRecord& rec = m.leaves[leaf];
      if (rec.key != key || rec.count == 0) continue;
      ++report.sparse_leaves_removed;
      report.sparse_points_removed += rec.count;
      for (std::uint32_t j = lists.head[leaf]; j != kNone; j = lists.next[j])
        if (!lists.dead[j]) {
          lists.dead[j] = 1;
          drops.push_back(m.point_src[j]);
        }
      m.removeCounts(leaf, rec.count);
      removed[leaf] = 1;
      erase_keys.push_back(rec.key);
    }
    m.dirty_cells.push_back(cell);  // the drop changes the neighbours' counts: the next pass
  }
  for (const octomap::OcTreeKey& k : erase_keys) m.tree.eraseLeaf(k);

  // 5. Compact leaves and points.
  std::vector<std::uint32_t> new_leaf(m.leaves.size(), kNone);
  std::size_t kept_leaves = 0;
  for (std::size_t l = 0; l < m.leaves.size(); ++l) {
    if (removed[l]) continue;
    new_leaf[l] = static_cast<std::uint32_t>(kept_leaves);
    m.leaves[l].node->setValue(new_leaf[l]);
    m.leaves[kept_leaves++] = m.leaves[l];
  }
  m.leaves.resize(kept_leaves);
  std::size_t out = 0;
  for (std::size_t j = 0; j < m.points.size(); ++j) {
    if (lists.dead[j]) continue;
    m.points[out] = m.points[j];
    m.point_leaf[out] = new_leaf[m.point_leaf[j]];
    m.point_src[out] = m.point_src[j];
    ++out;
  }
  m.points.resize(out);
  m.point_leaf.resize(out);
  m.point_src.resize(out);

  // 6. Dropped points leave their keyframes; the survivors' indices follow.
  std::sort(drops.begin(), drops.end(), [](PointSource a, PointSource b) {
    return a.ordinal < b.ordinal || (a.ordinal == b.ordinal && a.index < b.index);
  });
  std::vector<std::vector<std::uint32_t>> remap(n_ord);
  for (std::size_t d = 0; d < drops.size();) {
    const std::uint32_t o = drops[d].ordinal;
    const std::uint32_t slot = slot_of[o];
    const std::vector<MapPoint>& old_points = store.at(slot).points;
    std::vector<std::uint32_t>& index_map = remap[o];
    index_map.assign(old_points.size(), kNone);
    std::vector<MapPoint> kept;
    kept.reserve(old_points.size());
    for (std::size_t i = 0; i < old_points.size(); ++i) {
      if (d < drops.size() && drops[d].ordinal == o && drops[d].index == i) {
        ++d;
        continue;
      }
      index_map[i] = static_cast<std::uint32_t>(kept.size());
      kept.push_back(old_points[i]);
    }
    store.replacePoints(slot, std::move(kept));
  }
  if (!drops.empty())
    for (PointSource& s : m.point_src)
      if (!remap[s.ordinal].empty()) s.index = remap[s.ordinal][s.index];

  report.kept_points = m.points.size();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  m.last_rebuild = report;
  m.built_pose_revision = store.poseRevision();
  return report;
}

}  // namespace rgbdi::mapping
