// Options of loop closure: the [loop] section (doc/loop.md lists every key with its unit).
#pragma once

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/loop/correction_gate.h"
#include "rgbdi/loop/loop_features.h"
#include "rgbdi/loop/loop_verifier.h"
#include "rgbdi/loop/place_recognizer.h"
#include "rgbdi/loop/pose_graph_options.h"

namespace rgbdi::loop {

struct LoopOptions {
  bool enable = true;  ///< loop closure on (rgbdi-slam --no-loop turns it off)
  /// [count] offline runs: a frame's online pose takes the drift correction known once keyframe
  /// k - lag has been through loop closing (k = keyframes handed out so far). A defined point,
  /// so threaded and sequential runs agree; live runs take what is ready.
  int offline_lag_keyframes = 1;
  int max_verified_candidates = 4;  ///< [count] candidates geometrically verified per keyframe
  int max_loops_per_keyframe = 1;   ///< [count] accepted loop edges per keyframe at most
  /// A keyframe joins loop closing (ORB features, place index, pose-graph node) only when it is
  /// at least this far from, or turned this much from, the previous one that joined (same
  /// segment); the others follow the correction of their neighbours. Bounds the cost per metre.
  /// Every keyframe joins while its segment is not yet joined to the origin (relocalisation).
  double min_keyframe_distance_m = 0.2;  ///< [m]
  double min_keyframe_angle_deg = 10.0;  ///< [deg]
  /// [count] after a loop is accepted the graph is solved once this many loop keyframes have
  /// passed since the last solve (and at the end of the run): bounds the solver's share.
  int solve_interval_keyframes = 5;

  /// Joining two parts not yet related (a new run to a loaded map, a segment after a reset to
  /// the earlier ones) is stricter than a loop: a false join puts a whole run in the wrong
  /// place. Each verified match must have this many PnP inliers ...
  int relocalize_min_inliers = 40;  ///< [count]
  /// ... and this many consecutive joining keyframes must agree on where the part goes ...
  int relocalize_consistent_keyframes = 2;  ///< [count] (1 = the first match joins)
  /// ... within these bounds (alignment of the part implied by each match) ...
  double relocalize_max_disagreement_m = 0.10;   ///< [m]
  double relocalize_max_disagreement_deg = 3.0;  ///< [deg]
  /// ... among matches of at most this many of the part's latest loop keyframes.
  int relocalize_window_keyframes = 6;  ///< [count]
  /// A part not yet joined (known so by the odometry thread) hands its keyframes to loop
  /// closing as soon as they are sure to stay keyframes, with the window's current pose, not
  /// when they leave the window: relocalisation a window (about 10 keyframes) earlier.
  bool relocalize_from_window = true;
  /// Before a join is made, the depth of the part's latest keyframes is compared (free space,
  /// as in verification step 7) with every keyframe of the other part within
  /// relocalize_check_radius_m of where the join puts them, not only with the matched ones: a
  /// repeated texture matches on one wall, but the furniture around it is elsewhere. More than
  /// relocalize_check_max_conflict_fraction of the compared samples conflicting refuses a
  /// join by views (its matches are dropped); a join by geometry, already confirmed by a second
  /// independent fit and ICP, is refused above relocalize_check_max_conflict_fraction_geometric
  /// (its local plan fitted the map's obstacles, so views from other sides conflict more).
  int relocalize_check_keyframes = 8;                              ///< [count] 0 = check off
  double relocalize_check_radius_m = 3.0;                          ///< [m]
  double relocalize_check_max_conflict_fraction = 0.01;            ///< [unitless]
  double relocalize_check_max_conflict_fraction_geometric = 0.05;  ///< [unitless]

  /// When accepted loops start correcting the odometry (correction_* keys).
  CorrectionGateOptions correction;
  LoopFeatureOptions features;
  PlaceRecognitionOptions place;
  LoopVerificationOptions verify;
  PoseGraphOptions graph;

  /// Reads and validates every [loop] key (ConfigError names file, key and range).
  static LoopOptions load(IniReader& ini);
};

}  // namespace rgbdi::loop
