#include "rgbdi/loop/loop_closer.h"

#include <algorithm>
#include <chrono>

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

Eigen::Isometry3d LoopCloser::drift(int segment) const {
  for (const SegmentState& s : graph_.segments())
    if (s.segment == segment) return graph_.drift(segment);
  return Eigen::Isometry3d::Identity();
}

LoopUpdate LoopCloser::process(LoopKeyframe kf) {
  LoopUpdate update;
  ++stats_.keyframes;
  graph_.addNode(kf.id, kf.segment, kf.T_world_body_odom);
  kf.T_world_body = graph_.pose(kf.id);  // the segment's current drift applied

  const auto t_rec = Clock::now();
  const std::vector<PlaceCandidate> candidates = recognizer_.process(kf);
  stats_.recognition_ms_total += msSince(t_rec);
  stats_.candidates += candidates.size();

  const auto t_ver = Clock::now();
  int verified = 0;
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
    LoopRecord r;
    r.constraint = v.constraint;
    r.edge_id =
        graph_.addLoopEdge(v.constraint.from_id, v.constraint.to_id, v.constraint.T_from_to);
    r.by_proximity = c.by_proximity;
    r.t_query = kf.t;
    loops_.push_back(r);
    ++update.accepted;
    ++stats_.accepted;
  }
  stats_.verification_ms_total += msSince(t_ver);

  if (update.accepted > 0) solve_pending_ = true;
  ++keyframes_since_solve_;
  if (solve_pending_ &&
      keyframes_since_solve_ >= static_cast<std::uint64_t>(options_.solve_interval_keyframes))
    solve(update);

  slot_of_[kf.id] = keyframes_.size();
  keyframes_.push_back(std::move(kf));
  if (update.solved) recognizer_.updatePoses(correctedPoses());
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
  for (const LoopKeyframe& k : keyframes_) b += descriptorBytes(k.descriptors);
  b +=
      graph_.nodes().capacity() * sizeof(GraphNode) + graph_.edges().capacity() * sizeof(GraphEdge);
  return b;
}

}  // namespace rgbdi::loop
