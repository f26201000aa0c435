// Geometric relocalisation as a stage of the SLAM system (doc/maps.md "Geometric
// relocalisation"). While the run's current part is not placed in the loaded map, loop closing
// hands the part's latest depth (its keyframes' depth grids over submap_path_m of path) to
// this stage's own thread every attempt_interval_m; the search result of an attempt made at
// loop keyframe k is taken back on the loop-closing thread at keyframe k + result_lag_keyframes
// (offline: waiting for it, a defined point, so threaded and sequential runs agree; live: only
// once it is ready). Fits go through FitConfirmation; a confirmed one becomes a join
// (LoopCloser::joinByAlignment), unless visual relocalisation placed the part first. Once the
// part is in the map's frame (either way), every track_interval_m of path its latest depth is
// refined against the map by ICP from its present pose on the same thread, with the same lag,
// and a passing fit adds loop edges (LoopCloser::trackByAlignment): tracking.
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/stage_worker.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/map/map_data.h"
#include "rgbdi/reloc/fit_confirmation.h"
#include "rgbdi/reloc/geometric_relocaliser.h"
#include "rgbdi/reloc/reloc_options.h"

namespace rgbdi::system {

/// What the stage did (summary.json map_session.geometric, progress line).
struct GeoRelocReport {
  std::uint64_t attempts = 0;  ///< searches started
  std::uint64_t results = 0;   ///< searches whose result was taken
  std::uint64_t too_little = 0, no_place = 0, ambiguous = 0, no_height = 0, unrefined = 0, fits = 0;
  std::uint64_t disagreements = 0;  ///< fits that did not confirm the proposal before them
  std::uint64_t confirmed = 0;      ///< confirmed fits handed to loop closing as joins
  std::uint64_t joined = 0;         ///< of those, joins made
  /// The latest result: its outcome and the number of distinct places it saw (why it waits).
  std::string last_outcome = "none";
  int last_places = 0;
  int last_candidates = 0;
  int max_places = 0;                   ///< most distinct places of one attempt
  std::uint64_t searched = 0;           ///< searches the worker finished
  double ms_total = 0.0, ms_max = 0.0;  ///< [ms] wall time of the searches (worker thread)
  double map_build_ms = 0.0;            ///< [ms] the map's plan, built on the worker thread
  /// Tracking after the join (RelocOptions::track_*): fits started and taken, by outcome (the
  /// loop edges they added: LoopStats::tracking_*), and their cost on the worker thread.
  std::uint64_t track_attempts = 0, track_results = 0, track_fits = 0, track_unrefined = 0,
                track_too_far = 0, track_too_little = 0;
  double track_ms_total = 0.0, track_ms_max = 0.0;  ///< [ms]
  double track_correction_max_m = 0.0;  ///< [m] largest correction of an accepted tracking fit
};

class GeoRelocStage {
 public:
  /// `map` must hold the loaded map; T_body_cam of the run (= the map's).
  GeoRelocStage(const reloc::RelocOptions& options, std::shared_ptr<const map::MapData> map,
                const Eigen::Isometry3d& T_body_cam, bool threaded, bool live);
  ~GeoRelocStage();
  /// Loop-closing thread, after closer.process() of a keyframe (the closer's newest): takes
  /// due results (may join: returns true when the graph was solved), then starts an attempt
  /// when due. `cam`: the colour camera of the keyframes.
  bool afterKeyframe(loop::LoopCloser& closer, const PinholeCamera& cam);
  /// End of the run, loop-closing thread stopped: waits for the tracking fits still on their
  /// way and takes them (their edges correct the final trajectory; a defined point, so offline
  /// runs stay deterministic); search results not yet taken are dropped (no join at the end).
  /// Returns true when the graph was solved.
  bool takeTrackingAtEnd(loop::LoopCloser& closer);
  /// Stops the worker (results not yet taken are dropped: the run has ended).
  void finish();
  /// Safe from any thread.
  GeoRelocReport report() const;
  /// Every result taken, in order (read after the run: loop-closing thread state).
  const std::vector<reloc::RelocFit>& taken() const { return taken_; }

 private:
  void handle(reloc::RelocJob& job);
  /// A search job (track false: up to submap_max_path_m of path) or a tracking job (the part in
  /// the map's frame, submap_path_m of path, its latest track_keyframes poses).
  reloc::RelocJob makeJob(const loop::LoopCloser& closer, const PinholeCamera& cam,
                          bool track) const;
  /// Takes a tracking result: loop edges when it passed (true when the graph was solved).
  bool takeTrack(const reloc::RelocFit& fit, loop::LoopCloser& closer);

  reloc::RelocOptions options_;
  std::shared_ptr<const map::MapData> map_;
  Eigen::Isometry3d T_body_cam_;
  bool live_ = false;
  // Worker thread.
  std::unique_ptr<reloc::GeometricRelocaliser> relocaliser_;
  // Shared (results by job number; report).
  mutable std::mutex mutex_;
  std::vector<reloc::RelocFit> results_;  ///< index = job number - 1
  GeoRelocReport report_;
  // Loop-closing thread.
  reloc::FitConfirmation confirm_;
  std::vector<reloc::RelocFit> taken_;
  struct Pending {
    std::uint64_t job;
    std::uint64_t due;  ///< loop keyframe count at which the result is taken
  };
  std::deque<Pending> pending_;
  std::uint64_t keyframes_ = 0;  ///< loop keyframes seen
  std::uint64_t jobs_ = 0;
  int segment_ = -1;
  double last_attempt_travelled_ = -1e300;
  double last_track_travelled_ = -1e300;
  std::unique_ptr<StageWorker<reloc::RelocJob>> worker_;  ///< last: joined first
};

}  // namespace rgbdi::system
