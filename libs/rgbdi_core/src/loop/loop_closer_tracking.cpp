// LoopCloser::trackByAlignment: after a part joined a loaded map, later fits of its depth
// against the map (GeoRelocStage's tracking) become loop edges to the map's keyframes, so the
// pose graph averages many fits instead of keeping the join's one.
#include "rgbdi/loop/loop_closer.h"

namespace rgbdi::loop {

LoopUpdate LoopCloser::trackByAlignment(
    int segment, const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& placed,
    double max_distance_m, double sigma_pos_m, double sigma_yaw_rad) {
  LoopUpdate update;
  if (!hasMap() || segment < 1 || !connectedToOrigin(segment) || placed.empty()) return update;
  // The part's keyframes where the fit puts them, each with the nearest map keyframe (the map's
  // keyframes come first in keyframes_).
  std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>> part;
  std::vector<std::uint64_t> nearest_map;
  const auto any_keyframe = [](const LoopKeyframe&) { return true; };
  for (const auto& [id, T_map_body] : placed) {
    const auto it = slot_of_.find(id);
    if (it == slot_of_.end() || keyframes_[it->second].segment != segment) continue;
    const LoopKeyframe* nearest =
        nearestKeyframe(T_map_body.translation(), max_distance_m, map_keyframes_, any_keyframe);
    if (!nearest) continue;
    part.emplace_back(&keyframes_[it->second], T_map_body);
    nearest_map.push_back(nearest->id);
  }
  if (part.empty()) {
    ++stats_.tracking_refused_no_neighbour;
    return update;
  }
  if (options_.relocalize_check_keyframes > 0) {
    // The join's free-space check, against the map's keyframes only (the part itself is in the
    // map's component now).
    const FreeSpaceTally tally = freeSpaceAgainst(part, map_keyframes_, any_keyframe);
    if (refusedByFreeSpace(tally, options_.relocalize_check_max_conflict_fraction_geometric)) {
      ++stats_.tracking_refused_free_space;
      return update;
    }
  }
  for (std::size_t k = 0; k < part.size(); ++k) {
    LoopRecord r;
    r.constraint.from_id = nearest_map[k];
    r.constraint.to_id = part[k].first->id;
    r.constraint.T_from_to = graph_.pose(nearest_map[k]).inverse() * part[k].second;
    r.edge_id = graph_.addLoopEdge(r.constraint.from_id, r.constraint.to_id, r.constraint.T_from_to,
                                   sigma_pos_m, sigma_yaw_rad);
    r.t_query = part[k].first->t - t_shift_;
    r.geometric = true;
    r.tracking = true;
    loops_.push_back(r);
    ++update.accepted;
    ++stats_.accepted;
  }
  ++stats_.tracking_fits;
  solve(update);
  recognizer_.updatePoses(correctedPoses());
  return update;
}

}  // namespace rgbdi::loop
