// PointMap::update: the map after a loop correction, touching only the keyframes that moved,
// equal to PointMap::rebuild on the same store (see point_map.h for the rules it reproduces).
// Its cost is that of the moved points (removal, re-insertion, the isolated-leaf rule around
// the cells they left and entered) plus O(keyframes) checks; no pass over the whole map.
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "mapping/point_map_impl.h"
#include "rgbdi/mapping/point_map.h"

namespace rgbdi::mapping {

using detail::kNone;
using detail::PointMapState;
using detail::PointSource;

RebuildReport PointMap::update(KeyframeStore& store, const std::vector<std::uint64_t>& moved_ids) {
  const auto start = std::chrono::steady_clock::now();
  PointMapState& m = *impl_;
  if (m.untracked_points > 0)
    throw std::logic_error("PointMap::update: " + std::to_string(m.untracked_points) +
                           " points were inserted without a keyframe id (use rebuild)");
  RebuildReport report;
  report.keyframes = store.size();
  report.input_points = store.pointCount();
  // The map and the store must agree on whose points the map holds.
  for (std::size_t o = 0; o < m.keyframe_slots.size(); ++o)
    if (!m.keyframe_slots[o].empty() && !store.contains(m.ordinal_id[o]))
      throw std::logic_error("PointMap::update: the map holds points of keyframe " +
                             std::to_string(m.ordinal_id[o]) + ", which is not in the store");

  // The moved keyframes that have points in the map, in id order (rebuild's order).
  std::vector<std::uint32_t> moved;
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
    const std::size_t held = m.keyframe_slots[it->second].size();
    if (held != store.get(id).points.size())
      throw std::logic_error("PointMap::update: keyframe " + std::to_string(id) + " keeps " +
                             std::to_string(store.get(id).points.size()) +
                             " points, the map holds " + std::to_string(held));
    moved.push_back(it->second);
  }
  std::sort(moved.begin(), moved.end(),
            [&](std::uint32_t a, std::uint32_t b) { return m.ordinal_id[a] < m.ordinal_id[b]; });
  moved.erase(std::unique(moved.begin(), moved.end()), moved.end());

  // 1. The moved keyframes' points leave their leaves but keep their slots, which they take
  // again when re-inserted (no slot moves for them). A leaf left empty is no leaf, as in a
  // rebuild, unless a re-inserted point lands there again.
  for (std::uint32_t o : moved)
    for (std::uint32_t j : m.keyframe_slots[o]) m.detachPoint(j);

  // 2. Re-insert them at their new poses. A full leaf keeps the points that come first in
  // (id, index) order: the arriving point replaces the leaf's last one if it comes before it.
  auto before = [&](PointSource a, PointSource b) {
    const std::uint64_t ia = m.ordinal_id[a.ordinal], ib = m.ordinal_id[b.ordinal];
    return ia < ib || (ia == ib && a.index < b.index);
  };
  std::vector<PointSource> drops;  // kept points that leave the map
  for (std::uint32_t o : moved) {
    const Keyframe& kf = store.get(m.ordinal_id[o]);
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      const MapPoint& p = kf.points[i];
      const PointSource src{o, static_cast<std::uint32_t>(i)};
      const Eigen::Vector3d p_world = kf.T_world_cam * p.p_cam.cast<double>();
      const std::uint32_t leaf = m.leafAt(p_world);
      if (leaf == kNone) {
        ++report.outside_extent;
        drops.push_back(src);
        m.removePoint(m.keyframe_slots[o][i]);
        continue;
      }
      if (m.leaves[leaf].count >= m.capacity) {
        ++report.rejected_full_leaf;
        std::uint32_t last = m.leaves[leaf].head;
        for (std::uint32_t j = m.point_next[last]; j != kNone; j = m.point_next[j])
          if (before(m.point_src[last], m.point_src[j])) last = j;
        if (!before(src, m.point_src[last])) {
          drops.push_back(src);
          m.removePoint(m.keyframe_slots[o][i]);
          continue;
        }
        drops.push_back(m.point_src[last]);
        m.removePoint(last);  // may move a detached point: its keyframe's slots follow
      }
      m.attachPoint(m.keyframe_slots[o][i], leaf, p_world);
    }
  }

  // 3. The isolated-leaf rule where anything changed since it last ran (insertions between
  // loops included), then the dropped points leave their keyframes.
  return m.finishPass(drops, store, report, start);
}

}  // namespace rgbdi::mapping
