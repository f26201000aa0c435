#include "rgbdi/loop/loop_closer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

namespace rgbdi::loop {
namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
std::size_t descriptorBytes(const mapping::DescriptorSet& d) {
  return d.data.capacity() + d.keypoints_uv.capacity() * sizeof(Eigen::Vector2f) +
         d.keypoints_p_cam.capacity() * sizeof(Eigen::Vector3f) + d.type.capacity();
}
}  // namespace

LoopCloser::LoopCloser(const LoopOptions& options, const PinholeCamera& colour_cam,
                       const Eigen::Isometry3d& T_body_cam)
    : options_(options),
      verifier_(options.verify, colour_cam, T_body_cam),
      recognizer_(options.place),
      graph_(options.graph) {}

void LoopCloser::loadMap(const std::vector<LoopKeyframe>& places) {
  if (!keyframes_.empty())
    throw std::logic_error("LoopCloser::loadMap: keyframes were processed already");
  for (const LoopKeyframe& kf : places) {
    graph_.addFixedNode(kf.id, 0, kf.T_world_body);
    LoopKeyframe stored = kf;
    stored.segment = 0;  // the map is one fixed part, whatever sessions built it
    stored.T_world_body_odom = kf.T_world_body;
    recognizer_.insert(stored);
    slot_of_[stored.id] = keyframes_.size();
    keyframes_.push_back(std::move(stored));
  }
  map_keyframes_ = keyframes_.size();
}

bool LoopCloser::connectedToOrigin(int segment) const {
  for (const SegmentState& s : graph_.segments())
    if (s.segment == segment) return s.connected_to_origin;
  return false;
}

Eigen::Isometry3d LoopCloser::drift(int segment) const {
  for (const SegmentState& s : graph_.segments())
    if (s.segment == segment) return graph_.drift(segment);
  return Eigen::Isometry3d::Identity();
}

LoopUpdate LoopCloser::process(LoopKeyframe kf) {
  LoopUpdate update;
  if (hasMap()) {
    if (kf.segment < 1)
      throw std::invalid_argument("LoopCloser::process: keyframe " + std::to_string(kf.id) +
                                  " has segment " + std::to_string(kf.segment) +
                                  ", but segment 0 is the loaded map");
    if (!shift_set_) {
      // The run's clock and path length continue after the map's, so that recency exclusion
      // treats every map keyframe as old.
      const LoopKeyframe& last = keyframes_.back();
      t_shift_ = std::max(0.0, last.t + options_.place.exclude_recent_s + 1.0 - kf.t);
      travelled_shift_ = last.travelled_m + options_.place.exclude_recent_m + 1.0;
      shift_set_ = true;
    }
    kf.t += t_shift_;
    kf.travelled_m += travelled_shift_;
  }
  ++stats_.keyframes;
  graph_.addNode(kf.id, kf.segment, kf.T_world_body_odom, kf.bridged_s);
  kf.T_world_body = graph_.pose(kf.id);  // the segment's current drift applied

  const auto t_rec = Clock::now();
  // The predicate only where another part exists: with none, every candidate is related and
  // the recognizer need not query a keyframe that has no reference score.
  std::function<bool(int)> unrelated;
  for (const SegmentState& s : graph_.segments())
    if (s.segment != kf.segment && !graph_.connected(s.segment, kf.segment)) {
      unrelated = [this, &kf](int segment) {
        return segment != kf.segment && !graph_.connected(segment, kf.segment);
      };
      break;
    }
  const std::vector<PlaceCandidate> candidates = recognizer_.process(kf, unrelated);
  stats_.recognition_ms_total += msSince(t_rec);
  stats_.candidates += candidates.size();

  const auto t_ver = Clock::now();
  int verified = 0;
  bool join_matched = false;
  for (const PlaceCandidate& c : candidates) {
    if (c.by_proximity) ++stats_.candidates_by_proximity;
    if (verified >= options_.max_verified_candidates) break;
    if (update.accepted >= options_.max_loops_per_keyframe) break;
    const auto it = slot_of_.find(c.id);
    if (it == slot_of_.end()) continue;
    LoopKeyframe& cand = keyframes_[it->second];
    cand.T_world_body = graph_.pose(cand.id);
    const bool related = cand.segment == kf.segment || graph_.connected(cand.segment, kf.segment);
    ++verified;
    ++stats_.verified;
    const LoopVerification v = verifier_.verify(kf, cand, related);
    if (!v.accepted) {
      ++stats_.rejected[static_cast<std::size_t>(v.reason)];
      continue;
    }
    if (!related) {
      // Every joining candidate is verified: two places matching equally well is what
      // tells an aliased view (tryJoin below refuses to choose).
      join_matched = addJoinMatch(kf, cand, v, c.by_proximity) || join_matched;
      continue;
    }
    LoopRecord r;
    r.constraint = v.constraint;
    r.edge_id =
        graph_.addLoopEdge(v.constraint.from_id, v.constraint.to_id, v.constraint.T_from_to);
    r.by_proximity = c.by_proximity;
    r.t_query = kf.t - t_shift_;
    if (cand.segment == kf.segment) {
      // Within one segment the odometry has its own estimate of the same relative pose.
      const LoopDisagreement d =
          loopDisagreement(v.constraint, cand.T_world_body_odom.inverse() * kf.T_world_body_odom,
                           options_.correction);
      r.disagreement_sigmas = d.sigmas;
      r.shows_drift = d.shows_drift;
      if (!d.shows_drift) ++stats_.within_odometry_uncertainty;
    }
    correcting_ = correcting_ || r.shows_drift;
    loops_.push_back(r);
    ++update.accepted;
    ++stats_.accepted;
  }
  if (join_matched) tryJoin(kf, update);
  stats_.verification_ms_total += msSince(t_ver);

  // Loops that agree with the odometry wait in the graph: solved only once one shows drift.
  if (update.accepted > 0 && correcting_) solve_pending_ = true;
  ++keyframes_since_solve_;
  if (solve_pending_ &&
      keyframes_since_solve_ >= static_cast<std::uint64_t>(options_.solve_interval_keyframes))
    solve(update);

  slot_of_[kf.id] = keyframes_.size();
  keyframes_.push_back(std::move(kf));
  if (update.solved) recognizer_.updatePoses(correctedPoses());
  return update;
}

bool LoopCloser::addJoinMatch(const LoopKeyframe& kf, const LoopKeyframe& cand,
                              const LoopVerification& v, bool by_proximity) {
  if (v.constraint.pnp_inliers < options_.relocalize_min_inliers) {
    ++stats_.join_matches_weak;
    return false;
  }
  int target = cand.segment;
  for (const SegmentState& s : graph_.segments())
    if (s.segment == cand.segment) target = s.component;
  PendingJoin p;
  p.record.constraint = v.constraint;
  p.record.by_proximity = by_proximity;
  p.record.t_query = kf.t - t_shift_;
  p.query_index = stats_.keyframes;
  p.query_segment = kf.segment;
  p.target_component = target;
  // Where this match puts the query's part: its current frame -> the candidate's frame.
  p.A = graph_.pose(cand.id) * v.constraint.T_from_to * kf.T_world_body.inverse();

  // Keep only recent matches of this part; older ones were never confirmed.
  const std::uint64_t window = static_cast<std::uint64_t>(options_.relocalize_window_keyframes);
  const auto stale = [&](const PendingJoin& q) {
    return q.query_segment != kf.segment || q.query_index + window <= p.query_index;
  };
  const auto n_before = pending_joins_.size();
  pending_joins_.erase(std::remove_if(pending_joins_.begin(), pending_joins_.end(), stale),
                       pending_joins_.end());
  stats_.join_matches_dropped += n_before - pending_joins_.size();
  pending_joins_.push_back(p);
  return true;
}

bool LoopCloser::tryJoin(const LoopKeyframe& kf, LoopUpdate& update) {
  // Whether two pending matches put the part in the same place (judged at kf's position).
  const Eigen::Vector3d x = kf.T_world_body.translation();
  const double max_yaw = options_.relocalize_max_disagreement_deg * M_PI / 180.0;
  const auto agree = [&](const PendingJoin& a, const PendingJoin& b) {
    if (a.target_component != b.target_component) return false;
    const Eigen::Isometry3d E = a.A.inverse() * b.A;
    const double yaw = std::abs(std::atan2(E.linear()(1, 0), E.linear()(0, 0)));
    return (a.A * x - b.A * x).norm() <= options_.relocalize_max_disagreement_m && yaw <= max_yaw;
  };
  // The matches agreeing with one of kf's own matches, counted by distinct query keyframe: the
  // confirmations must come from other keyframes. The best such cluster is the candidate join.
  std::vector<std::size_t> best;
  std::size_t best_own = 0;  // kf's own match in the best cluster
  int best_keyframes = 0;
  for (std::size_t i = 0; i < pending_joins_.size(); ++i) {
    if (pending_joins_[i].query_index != stats_.keyframes) continue;  // not one of kf's
    std::vector<std::size_t> cluster;
    std::vector<std::uint64_t> queries;
    for (std::size_t k = 0; k < pending_joins_.size(); ++k) {
      if (!agree(pending_joins_[i], pending_joins_[k])) continue;
      cluster.push_back(k);
      if (std::find(queries.begin(), queries.end(), pending_joins_[k].query_index) == queries.end())
        queries.push_back(pending_joins_[k].query_index);
    }
    if (static_cast<int>(queries.size()) > best_keyframes) {
      best_keyframes = static_cast<int>(queries.size());
      best = std::move(cluster);
      best_own = i;
    }
  }
  if (best_keyframes < options_.relocalize_consistent_keyframes) return false;
  // A pending match that puts the part elsewhere makes the place ambiguous (a repeated texture,
  // identical rooms): wait until only one alignment is seen, or the matches age out.
  for (std::size_t k = 0; k < pending_joins_.size(); ++k)
    if (std::find(best.begin(), best.end(), k) == best.end() &&
        pending_joins_[k].target_component == pending_joins_[best.front()].target_component) {
      ++stats_.joins_ambiguous;
      return false;
    }

  // The whole neighbourhood must agree, not only the matched views.
  JoinRecord j;
  if (options_.relocalize_check_keyframes > 0) {
    const PendingJoin& own = pending_joins_[best_own];
    const FreeSpaceTally tally = joinFreeSpace(kf, own.A, own.target_component);
    j.check_compared = tally.compared;
    j.check_conflicts = tally.conflicts;
    if (refusedByFreeSpace(tally, options_.relocalize_check_max_conflict_fraction)) {
      ++stats_.joins_refused_free_space;
      stats_.join_matches_dropped += best.size();
      std::vector<PendingJoin> kept;
      for (std::size_t k = 0; k < pending_joins_.size(); ++k)
        if (std::find(best.begin(), best.end(), k) == best.end()) kept.push_back(pending_joins_[k]);
      pending_joins_ = std::move(kept);
      return false;
    }
  }
  j.segment = kf.segment;
  j.to_segment = pending_joins_[best.front()].target_component;
  j.t_query = kf.t - t_shift_;
  j.query_id = kf.id;
  for (std::size_t i : best) {
    LoopRecord r = pending_joins_[i].record;
    r.edge_id =
        graph_.addLoopEdge(r.constraint.from_id, r.constraint.to_id, r.constraint.T_from_to);
    loops_.push_back(r);
    ++update.accepted;
    ++stats_.accepted;
    ++j.loop_edges;
  }
  stats_.join_matches_dropped += pending_joins_.size() - best.size();
  pending_joins_.clear();
  joins_.push_back(j);
  ++stats_.joins;
  // Solved now, not after solve_interval_keyframes: the part's poses jump into the other frame.
  correcting_ = true;
  solve_pending_ = true;
  keyframes_since_solve_ = static_cast<std::uint64_t>(options_.solve_interval_keyframes);
  return true;
}

FreeSpaceTally LoopCloser::joinFreeSpace(const LoopKeyframe& kf, const Eigen::Isometry3d& A,
                                         int target_component) const {
  // The part's latest keyframes, kf first (it is not stored yet), at the poses A gives them.
  std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>> part{{&kf, A * kf.T_world_body}};
  for (auto it = keyframes_.rbegin();
       it != keyframes_.rend() &&
       part.size() < static_cast<std::size_t>(options_.relocalize_check_keyframes);
       ++it)
    if (it->segment == kf.segment) part.emplace_back(&*it, A * graph_.pose(it->id));
  return neighbourhoodFreeSpace(part, target_component);
}

FreeSpaceTally LoopCloser::neighbourhoodFreeSpace(
    const std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>>& part,
    int target_component) const {
  std::vector<int> target_segments;
  for (const SegmentState& s : graph_.segments())
    if (s.component == target_component) target_segments.push_back(s.segment);
  return freeSpaceAgainst(part, keyframes_.size(), [&](const LoopKeyframe& k) {
    return std::find(target_segments.begin(), target_segments.end(), k.segment) !=
           target_segments.end();
  });
}

FreeSpaceTally LoopCloser::freeSpaceAgainst(
    const std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>>& part, std::size_t count,
    const KeyframeFilter& in_target) const {
  const double r2 = options_.relocalize_check_radius_m * options_.relocalize_check_radius_m;
  FreeSpaceTally tally;
  for (std::size_t i = 0; i < std::min(count, keyframes_.size()); ++i) {
    const LoopKeyframe& t = keyframes_[i];
    if (!in_target(t)) continue;
    const Eigen::Isometry3d T_t = graph_.pose(t.id);
    for (const auto& [p, T_p] : part)
      if ((T_t.translation() - T_p.translation()).squaredNorm() <= r2)
        tally += verifier_.compareFreeSpace(*p, T_p, t, T_t);
  }
  return tally;
}

bool LoopCloser::refusedByFreeSpace(const FreeSpaceTally& tally,
                                    double max_conflict_fraction) const {
  return tally.compared >= options_.verify.freespace_min_samples &&
         tally.conflicts > max_conflict_fraction * tally.compared;
}

const LoopKeyframe* LoopCloser::nearestKeyframe(const Eigen::Vector3d& p, double max_distance_m,
                                                std::size_t count,
                                                const KeyframeFilter& in_target) const {
  double best = max_distance_m * max_distance_m;
  const LoopKeyframe* nearest = nullptr;
  for (std::size_t i = 0; i < std::min(count, keyframes_.size()); ++i) {
    const LoopKeyframe& t = keyframes_[i];
    if (!in_target(t)) continue;
    const double d2 = (graph_.pose(t.id).translation() - p).squaredNorm();
    if (d2 < best) {
      best = d2;
      nearest = &t;
    }
  }
  return nearest;
}

LoopUpdate LoopCloser::joinByAlignment(int segment, const Eigen::Isometry3d& T_origin_part,
                                       int max_keyframes, double max_distance_m, double t_query) {
  LoopUpdate update;
  if (connectedToOrigin(segment)) return update;
  // The part's latest keyframes, newest first, where the alignment puts them.
  std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>> part;
  for (auto it = keyframes_.rbegin();
       it != keyframes_.rend() && part.size() < static_cast<std::size_t>(max_keyframes); ++it)
    if (it->segment == segment) part.emplace_back(&*it, T_origin_part * graph_.pose(it->id));
  // Each to the nearest keyframe of the origin's part.
  std::vector<std::pair<const LoopKeyframe*, std::uint64_t>> edges;  // (part keyframe, map id)
  for (const auto& [p, T_p] : part) {
    const LoopKeyframe* nearest = nearestKeyframe(
        T_p.translation(), max_distance_m, keyframes_.size(), [&](const LoopKeyframe& t) {
          return t.segment != segment && connectedToOrigin(t.segment);
        });
    if (nearest) edges.emplace_back(p, nearest->id);
  }
  if (edges.empty()) {
    ++stats_.geometric_refused_no_neighbour;
    return update;
  }
  JoinRecord j;
  j.geometric = true;
  if (options_.relocalize_check_keyframes > 0) {
    std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>> checked(
        part.begin(),
        part.begin() +
            static_cast<long>(std::min<std::size_t>(
                part.size(), static_cast<std::size_t>(options_.relocalize_check_keyframes))));
    const FreeSpaceTally tally = neighbourhoodFreeSpace(checked, 0);
    j.check_compared = tally.compared;
    j.check_conflicts = tally.conflicts;
    if (refusedByFreeSpace(tally, options_.relocalize_check_max_conflict_fraction_geometric)) {
      ++stats_.geometric_refused_free_space;
      return update;
    }
  }
  j.segment = segment;
  j.to_segment = 0;
  j.t_query = t_query;
  j.query_id = part.front().first->id;
  for (const auto& [p, map_id] : edges) {
    LoopRecord r;
    r.constraint.from_id = map_id;
    r.constraint.to_id = p->id;
    r.constraint.T_from_to = graph_.pose(map_id).inverse() * T_origin_part * graph_.pose(p->id);
    r.edge_id =
        graph_.addLoopEdge(r.constraint.from_id, r.constraint.to_id, r.constraint.T_from_to);
    r.t_query = p->t - t_shift_;  // the part keyframe's own stamp (run clock)
    r.geometric = true;
    loops_.push_back(r);
    ++update.accepted;
    ++stats_.accepted;
    ++j.loop_edges;
  }
  // Visual matches pending for this part are superseded by the join.
  const auto n_before = pending_joins_.size();
  pending_joins_.erase(
      std::remove_if(pending_joins_.begin(), pending_joins_.end(),
                     [&](const PendingJoin& q) { return q.query_segment == segment; }),
      pending_joins_.end());
  stats_.join_matches_dropped += n_before - pending_joins_.size();
  joins_.push_back(j);
  ++stats_.joins;
  ++stats_.joins_geometric;
  correcting_ = true;
  solve(update);
  recognizer_.updatePoses(correctedPoses());
  return update;
}

LoopUpdate LoopCloser::finish() {
  LoopUpdate update;
  if (solve_pending_) {
    solve(update);
    recognizer_.updatePoses(correctedPoses());
  }
  return update;
}

int LoopCloser::addExternalLoop(std::uint64_t from_id, std::uint64_t to_id,
                                const Eigen::Isometry3d& T_from_to) {
  LoopRecord r;
  r.edge_id = graph_.addLoopEdge(from_id, to_id, T_from_to);
  r.constraint.from_id = from_id;
  r.constraint.to_id = to_id;
  r.constraint.T_from_to = T_from_to;
  r.external = true;
  const auto it = slot_of_.find(to_id);
  r.t_query = it == slot_of_.end() ? 0.0 : keyframes_[it->second].t;
  loops_.push_back(r);
  ++stats_.external;
  correcting_ = true;
  solve_pending_ = true;
  return r.edge_id;
}

void LoopCloser::solve(LoopUpdate& update) {
  const auto t_solve = Clock::now();
  const PoseGraphSolveReport rep = graph_.solve();
  const double ms = msSince(t_solve);
  ++stats_.solves;
  stats_.solve_ms_total += ms;
  stats_.solve_ms_max = std::max(stats_.solve_ms_max, ms);
  stats_.solver_iterations_total += rep.iterations;
  for (int edge : rep.rolled_back_loop_edges) {
    for (LoopRecord& r : loops_)
      if (r.edge_id == edge && !r.rolled_back) {
        r.rolled_back = true;
        ++stats_.rolled_back;
        ++update.rolled_back;
      }
  }
  // The graph corrects while an active loop shows drift: once the last such loop is rolled
  // back, the loops left agree with the odometry, and so do the poses again.
  if (correcting_ && std::none_of(loops_.begin(), loops_.end(), [](const LoopRecord& r) {
        return r.shows_drift && !r.rolled_back;
      })) {
    graph_.resetToOdometry();
    correcting_ = false;
  }
  update.solved = true;
  solve_pending_ = false;
  keyframes_since_solve_ = 0;
}

std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> LoopCloser::correctedPoses() const {
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> out;
  out.reserve(keyframes_.size() + 1);
  for (const GraphNode& n : graph_.nodes()) out.emplace_back(n.id, graph_.pose(n.id));
  return out;
}

std::size_t LoopCloser::memoryBytes() const {
  std::size_t b = keyframes_.capacity() * sizeof(LoopKeyframe) + recognizer_.memoryBytes();
  for (const LoopKeyframe& k : keyframes_)
    b += descriptorBytes(k.descriptors) + k.depth_grid.depth_m.capacity() * sizeof(float);
  b +=
      graph_.nodes().capacity() * sizeof(GraphNode) + graph_.edges().capacity() * sizeof(GraphEdge);
  return b;
}

}  // namespace rgbdi::loop
