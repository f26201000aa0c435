// Loop closing for one keyframe at a time (paper sections 3.4, 4.4): place recognition proposes
// stored keyframes, geometric verification with metric depth accepts or rejects each (counted by
// reason), accepted loops become edges of the live 4-DOF pose graph, which is solved to
// convergence with wrong loops rolled back. Owned by one thread (the loop-closing stage).
//
// Joining parts that are not yet related (a run to a loaded map, a segment after an odometry
// reset to the earlier ones) is a relocalisation: stricter than a loop (more inliers, several
// consecutive keyframes agreeing on the part's alignment) and then done in one solve, which
// moves the joined part into the frame of the part it joined (the map's, when one is loaded).
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/loop/loop_keyframe.h"
#include "rgbdi/loop/loop_options.h"
#include "rgbdi/loop/loop_verifier.h"
#include "rgbdi/loop/place_recognizer.h"
#include "rgbdi/loop/pose_graph.h"

namespace rgbdi::loop {

/// One accepted loop.
struct LoopRecord {
  LoopConstraint constraint;  ///< from = older (candidate), to = newer (query)
  int edge_id = -1;           ///< edge of the pose graph
  bool by_proximity = false;  ///< proposed by the pose search, not by appearance
  double t_query = 0.0;       ///< [s] stamp of the query keyframe
  bool rolled_back = false;   ///< removed by a later solve (its residual exceeded the gate)
  bool external = false;      ///< added by addExternalLoop, not found by the closer
  /// Disagreement with the odometry in the loop's own sigmas (correction gate; 0 for loops
  /// between segments and external ones, which always correct)
  double disagreement_sigmas = 0.0;
  bool shows_drift = true;  ///< beyond the correction gate (or between segments, or external)
  bool geometric = false;   ///< an edge of a geometric join (joinByAlignment), not a verified view
  bool tracking = false;    ///< an edge of a tracking fit (trackByAlignment) after the join
};

/// One relocalisation: a part joined to another by verified loops.
struct JoinRecord {
  int segment = 0;       ///< segment of the query keyframes (the part that was moved)
  int to_segment = 0;    ///< lowest segment of the part it joined (0 = the map / the origin)
  double t_query = 0.0;  ///< [s] stamp (run clock) of the keyframe that completed the join
  std::uint64_t query_id = 0;
  int loop_edges = 0;  ///< loop edges added by the join
  /// The neighbourhood free-space check of the join (LoopOptions::relocalize_check_*): depth
  /// samples compared and conflicting (0 / 0 when the check is off or nothing was in view).
  int check_compared = 0;
  int check_conflicts = 0;
  bool geometric = false;  ///< made by joinByAlignment (geometric relocalisation)
};

struct LoopStats {
  std::uint64_t keyframes = 0;   ///< keyframes processed (all queried)
  std::uint64_t candidates = 0;  ///< proposed by place recognition
  std::uint64_t candidates_by_proximity = 0;
  std::uint64_t verified = 0;                                       ///< geometric verifications run
  std::array<std::uint64_t, kAllLoopRejections.size()> rejected{};  ///< by LoopRejection
  std::uint64_t accepted = 0;
  std::uint64_t external = 0;     ///< loops added by addExternalLoop (not in accepted)
  std::uint64_t rolled_back = 0;  ///< accepted or external loops removed by a solve
  /// accepted loops within the correction gate: agreeing with the odometry within their own
  /// uncertainty (kept in the graph; they correct once a loop beyond the gate came)
  std::uint64_t within_odometry_uncertainty = 0;
  std::uint64_t solves = 0;
  std::uint64_t joins = 0;                 ///< relocalisations (see JoinRecord)
  std::uint64_t join_matches_weak = 0;     ///< joining matches with too few PnP inliers
  std::uint64_t join_matches_dropped = 0;  ///< joining matches that no later keyframe confirmed
  /// Join decisions refused because pending matches put the part in two places (aliasing).
  std::uint64_t joins_ambiguous = 0;
  /// Joins refused by the neighbourhood free-space check (their matches were dropped).
  std::uint64_t joins_refused_free_space = 0;
  std::uint64_t joins_geometric = 0;  ///< joins made by joinByAlignment (in joins)
  /// joinByAlignment calls refused: by the neighbourhood free-space check, or no map keyframe
  /// near the part's keyframes.
  std::uint64_t geometric_refused_free_space = 0;
  std::uint64_t geometric_refused_no_neighbour = 0;
  /// trackByAlignment: fits that added loop edges, and those refused (free space, no map
  /// keyframe near).
  std::uint64_t tracking_fits = 0;
  std::uint64_t tracking_refused_free_space = 0;
  std::uint64_t tracking_refused_no_neighbour = 0;
  double features_ms_total = 0.0;     ///< ORB extraction (done by the caller, added by it)
  double recognition_ms_total = 0.0;  ///< index query + insertion
  double verification_ms_total = 0.0;
  double solve_ms_total = 0.0, solve_ms_max = 0.0;
  int solver_iterations_total = 0;
};

/// What processing one keyframe changed.
struct LoopUpdate {
  int accepted = 0;
  int rolled_back = 0;
  bool solved = false;  ///< the pose graph was solved: every corrected pose may have moved
};

class LoopCloser {
 public:
  LoopCloser(const LoopOptions& options, const PinholeCamera& colour_cam,
             const Eigen::Isometry3d& T_body_cam);

  /// Loads the keyframes of a saved map before the first process(): fixed graph nodes of
  /// segment 0 (the origin; the map's poses never change) that join the place index. The run's
  /// keyframes must then have segments >= 1 and ids above the map's; their stamps and distances
  /// are shifted after the map's inside loop closing (see timeShift()), so the map's keyframes
  /// count as old. Throws std::logic_error after process(), std::invalid_argument for keyframes
  /// out of id order or with inconsistent descriptors.
  void loadMap(const std::vector<LoopKeyframe>& places);
  bool hasMap() const { return map_keyframes_ > 0; }
  std::size_t mapKeyframes() const { return map_keyframes_; }
  /// [s] added to the run's stamps inside loop closing (0 without a map): keyframes() and the
  /// saved map use this shifted clock, LoopRecord::t_query and JoinRecord::t_query the run's.
  double timeShift() const { return t_shift_; }

  /// kf.descriptors must hold its ORB keypoints; kf.T_world_body is set here from the drift of
  /// its segment (the best estimate before this keyframe's own loops).
  LoopUpdate process(LoopKeyframe kf);
  /// Solves the graph if loops were accepted since the last solve (end of the run).
  LoopUpdate finish();

  /// Adds a loop edge that place recognition and verification did not produce: the test hook
  /// the system tests use to inject a wrong loop and check that it is rolled back, and a way
  /// for a tool that knows a revisit to add it. T_from_to maps points of the `to` body frame
  /// into the `from` body frame (only x, y, z and yaw are used). The edge is solved with the
  /// next solve like an accepted loop (after solve_interval_keyframes more keyframes, or by
  /// finish()) and rolled back by the same gate; it appears in loops() with `external` set and
  /// is counted in stats().external. Call it from the thread that owns the closer (in a
  /// SlamSystem: between feeds of a sequential run). Returns the edge id; throws
  /// std::invalid_argument like PoseGraph4Dof::addLoopEdge (unknown node, from == to, a pose
  /// that is not finite and rigid).
  int addExternalLoop(std::uint64_t from_id, std::uint64_t to_id,
                      const Eigen::Isometry3d& T_from_to);

  /// Joins the part of `segment` (not yet related to the origin) to the origin (segment 0: the
  /// loaded map) by an alignment found elsewhere (geometric relocalisation): T_origin_part maps
  /// the part's current frame (its keyframes' poses now) into the origin's. Loop edges go from
  /// the map keyframe nearest to where the alignment puts each of the part's latest
  /// `max_keyframes` keyframes (within max_distance_m) to that keyframe; the neighbourhood
  /// free-space check of joins (relocalize_check_*) must pass; then the graph is solved at once.
  /// `t_query`: [s] run clock, for the JoinRecord. Returns the update (solved when joined).
  LoopUpdate joinByAlignment(int segment, const Eigen::Isometry3d& T_origin_part, int max_keyframes,
                             double max_distance_m, double t_query);

  /// Keeps a part already joined to a loaded map registered to it (geometric relocalisation's
  /// tracking): `placed` holds some of the part's keyframes (id, T_map_body where a fit against
  /// the map puts them). Each gets a loop edge from the loaded map's keyframe nearest it (within
  /// max_distance_m) with the given sigmas ([m], [rad]), after the neighbourhood free-space
  /// check of joins against the map's keyframes only; then the graph is solved. Nothing when
  /// the part is not joined to the map, no map is loaded, or a check refuses it.
  LoopUpdate trackByAlignment(
      int segment, const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& placed,
      double max_distance_m, double sigma_pos_m, double sigma_yaw_rad);

  /// Correction of `segment` (T_corrected * T_odom^-1); identity for a segment not seen yet.
  Eigen::Isometry3d drift(int segment) const;
  /// Corrected body pose of a processed keyframe (throws std::out_of_range naming the id).
  Eigen::Isometry3d pose(std::uint64_t id) const { return graph_.pose(id); }
  /// Corrected body poses of every processed keyframe, in id order.
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> correctedPoses() const;

  const PoseGraph4Dof& graph() const { return graph_; }
  const std::vector<LoopRecord>& loops() const { return loops_; }
  const std::vector<JoinRecord>& joins() const { return joins_; }
  /// True when `segment` is joined to the origin (segment 0 / the loaded map) by active loops.
  bool connectedToOrigin(int segment) const;
  /// Every processed keyframe (loaded map first), by id order; poses as of the last update.
  const std::vector<LoopKeyframe>& keyframes() const { return keyframes_; }
  const LoopStats& stats() const { return stats_; }
  /// Whether the pose graph corrects the odometry: while an active (not rolled back) loop is
  /// beyond the correction gate, or joins two segments, or was added from outside; otherwise
  /// the corrected poses are the odometry's.
  bool correcting() const { return correcting_; }
  LoopStats& mutableStats() { return stats_; }
  const PlaceRecognitionStats& placeStats() const { return recognizer_.stats(); }
  /// Bytes held for the stored keyframes (descriptors, keypoints, points) and the index.
  std::size_t memoryBytes() const;

 private:
  LoopOptions options_;
  LoopVerifier verifier_;
  PlaceRecognizer recognizer_;
  PoseGraph4Dof graph_;
  std::vector<LoopKeyframe> keyframes_;  ///< every processed keyframe, by id order
  std::unordered_map<std::uint64_t, std::size_t> slot_of_;
  std::vector<LoopRecord> loops_;
  LoopStats stats_;
  bool solve_pending_ = false;
  bool correcting_ = false;  ///< see correcting()
  std::uint64_t keyframes_since_solve_ = 0;

  /// A verified match joining two unrelated parts, waiting for consecutive confirmations.
  struct PendingJoin {
    LoopRecord record;
    std::uint64_t query_index = 0;  ///< keyframe counter of the query
    int query_segment = 0;
    int target_component = 0;
    Eigen::Isometry3d A = Eigen::Isometry3d::Identity();  ///< part's frame -> target's frame
  };
  std::vector<PendingJoin> pending_joins_;
  std::vector<JoinRecord> joins_;
  std::size_t map_keyframes_ = 0;
  double t_shift_ = 0.0, travelled_shift_ = 0.0;
  bool shift_set_ = false;

  void solve(LoopUpdate& update);
  /// Keeps an accepted match between unrelated parts as a pending join (false: too weak).
  bool addJoinMatch(const LoopKeyframe& kf, const LoopKeyframe& cand, const LoopVerification& v,
                    bool by_proximity);
  /// After kf's joining matches were added: joins kf's part when enough of its keyframes agree
  /// on one alignment and no pending match points elsewhere; true when it joined.
  bool tryJoin(const LoopKeyframe& kf, LoopUpdate& update);
  /// Free-space evidence of placing kf's part by A (part frame -> target frame): the part's
  /// latest keyframes (kf first) against every keyframe of target_component near where A puts
  /// them (LoopOptions::relocalize_check_*).
  FreeSpaceTally joinFreeSpace(const LoopKeyframe& kf, const Eigen::Isometry3d& A,
                               int target_component) const;
  /// The same for part keyframes already placed where the join puts them.
  FreeSpaceTally neighbourhoodFreeSpace(
      const std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>>& part,
      int target_component) const;
  /// Which keyframes a check or a search looks at.
  using KeyframeFilter = std::function<bool(const LoopKeyframe&)>;
  /// Free-space evidence of the placed part keyframes against those of the first `count`
  /// keyframes that `in_target` accepts and lie within relocalize_check_radius_m of one.
  FreeSpaceTally freeSpaceAgainst(
      const std::vector<std::pair<const LoopKeyframe*, Eigen::Isometry3d>>& part, std::size_t count,
      const KeyframeFilter& in_target) const;
  /// Enough samples compared and more than `max_conflict_fraction` of them in conflict.
  bool refusedByFreeSpace(const FreeSpaceTally& tally, double max_conflict_fraction) const;
  /// Among the first `count` keyframes that `in_target` accepts, the one nearest to p within
  /// max_distance_m (the first of equals), or null.
  const LoopKeyframe* nearestKeyframe(const Eigen::Vector3d& p, double max_distance_m,
                                      std::size_t count, const KeyframeFilter& in_target) const;
};

}  // namespace rgbdi::loop
