// Place recognition for loop closure: proposes stored keyframes that may show the place a new
// keyframe shows, for geometric verification.
//
// Per keyframe: the place index is queried with its ORB descriptors, leaving out the recent
// keyframes (by time AND by distance travelled, and at least the last few); scores are divided
// by the keyframe's score with its own predecessor (how similar two views of one place are right
// now, so no absolute threshold depends on the scene's texture; no query when the predecessor
// shares too little of the keyframe's keys to serve as that reference); a candidate is proposed
// only when its neighbourhood (stored keyframes close in time) also matched the previous N-1
// keyframes (temporal consistency). Stored keyframes of the same odometry segment near the
// current pose estimate are added as proximity candidates (small loops, where appearance alone
// is ambiguous). Then the keyframe joins the index. Per keyframe only id, segment, stamp,
// distance travelled and position are kept besides the index.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/loop/loop_keyframe.h"
#include "rgbdi/loop/place_index.h"

namespace rgbdi::loop {

/// [loop] keys with prefix place_. Defaults equal share/config.ini.
struct PlaceRecognitionOptions {
  PlaceIndexOptions index;  ///< place_index_tables, _key_bits, _max_key_keyframes, _seed
  int top_k = 5;            ///< [count] index matches examined per keyframe
  /// A stored keyframe is a candidate only when it is at least this much older ...
  double exclude_recent_s = 10.0;  ///< [s]
  double exclude_recent_m = 2.0;   ///< [m] ... and at least this much distance travelled back
  int exclude_recent_count = 5;    ///< [count] ... and not one of the last this many keyframes
  /// [unitless] score / (score of the keyframe with its predecessor) needed to be a candidate
  double min_normalised_score = 0.5;
  /// [unitless] the index is not queried when the score with the predecessor is below this
  /// fraction of the keyframe's score with itself (the view changed completely since the
  /// predecessor, e.g. a fast turn: normalising by a near-zero score would pass anything)
  double min_reference_ratio = 0.02;
  /// [count] consecutive keyframes whose candidates must agree (N; 1 = no consistency check)
  int consistency_keyframes = 2;
  /// [s] candidates of consecutive keyframes agree when their stamps differ by at most this
  double consistency_window_s = 3.0;
  /// [m] stored keyframes of the same segment within this distance of the current position
  /// estimate become proximity candidates; 0 disables
  double proximity_radius_m = 1.0;
  int proximity_max_candidates = 2;  ///< [count] nearest first; 0 disables

  /// Throws ConfigError when a value is out of range.
  void validate() const;
  /// Reads the place_ keys of [loop]; missing keys keep the defaults above.
  static PlaceRecognitionOptions load(IniReader& ini);
};

struct PlaceCandidate {
  std::uint64_t id = 0;
  double score = 0.0;             ///< index similarity (PlaceIndex::similarity)
  double normalised_score = 0.0;  ///< score / score with the predecessor (0 without a reference)
  bool by_proximity = false;      ///< proposed by the pose, not (only) by appearance
};

/// Counters for summary.json (sums over all processed keyframes).
struct PlaceRecognitionStats {
  std::uint64_t queried = 0;  ///< keyframes processed while the index held keyframes
  std::uint64_t no_reference =
      0;  ///< of those, not queried: too little shared with the predecessor
  std::uint64_t above_threshold = 0;        ///< matches reaching min_normalised_score
  std::uint64_t temporally_consistent = 0;  ///< appearance candidates returned
  std::uint64_t proximity = 0;              ///< proximity candidates returned
};

class PlaceRecognizer {
 public:
  /// Throws ConfigError on invalid options.
  explicit PlaceRecognizer(const PlaceRecognitionOptions& options = PlaceRecognitionOptions());

  /// Candidates for `kf` (appearance candidates best first by normalised score, then proximity
  /// candidates nearest first; no id twice), then adds kf. kf.id must be larger than every id
  /// processed so far, and kf.t and kf.travelled_m not smaller (std::invalid_argument
  /// otherwise, nothing changed).
  ///
  /// `unrelated(segment)`, when given, names segments whose frame is not yet related to kf's:
  /// their appearance candidates skip the temporal consistency check, because joining such a
  /// part is confirmed by several verified matches instead (LoopCloser's relocalisation rule),
  /// and waiting for consistent queries first would delay every relocalisation. The first
  /// keyframe of a segment (no predecessor of its own to normalise by) then proposes the
  /// unrelated parts' best matches without a score threshold.
  std::vector<PlaceCandidate> process(const LoopKeyframe& kf,
                                      const std::function<bool(int)>& unrelated = {});
  /// Adds kf without querying (rebuilding from a loaded map, in id order).
  void insert(const LoopKeyframe& kf);
  /// Corrected body poses after a pose-graph solve (only the positions are kept). Throws
  /// std::out_of_range naming an id that was never processed (nothing changed then).
  void updatePoses(const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& T_world_body);
  void clear();

  std::size_t size() const { return records_.size(); }
  const PlaceIndex& index() const { return index_; }
  const PlaceRecognitionStats& stats() const { return stats_; }
  /// Heap + object bytes of the index and the per-keyframe records.
  std::size_t memoryBytes() const;
  /// Position estimate of a stored keyframe (throws std::out_of_range when absent).
  Eigen::Vector3d position(std::uint64_t id) const;

 private:
  struct Record {
    std::uint64_t id;
    int segment;
    double t;
    double travelled_m;
    Eigen::Vector3d p_world_body;
  };
  /// A match of the previous keyframe that reached the threshold, with the number of
  /// consecutive keyframes (itself included) whose matches lie in its neighbourhood.
  struct Streak {
    double t;
    int length;
  };
  std::size_t slotOf(std::uint64_t id) const;  // size() when absent
  bool eligible(std::size_t slot, const LoopKeyframe& kf) const;
  /// Slots [0, end) are eligible as candidates for kf.
  std::size_t eligibleEnd(const LoopKeyframe& kf) const;
  void checkNewer(const LoopKeyframe& kf, const char* who) const;
  void add(const LoopKeyframe& kf, const PlaceKeys& keys);

  PlaceRecognitionOptions options_;
  PlaceIndex index_;
  std::vector<Record> records_;  ///< increasing id
  std::vector<Streak> previous_streaks_;
  PlaceRecognitionStats stats_;
};

}  // namespace rgbdi::loop
