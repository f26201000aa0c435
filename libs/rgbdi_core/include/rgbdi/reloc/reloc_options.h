// Options of geometric relocalisation in a saved map: the [relocalise] section (doc/maps.md
// "Geometric relocalisation" lists every key with its unit).
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::reloc {

/// How depth becomes a 2-D gravity-aligned plan of the world (PlanGrid).
struct PlanGridOptions {
  double resolution_m = 0.05;  ///< [m] cell side
  /// Height band, relative to the observing camera's height, whose surfaces are obstacles of
  /// the plan (walls, furniture); below it is floor, above it ceiling. Relative to the camera
  /// because a robot's camera stays at one height above its floor (ramps included).
  double band_min_m = -0.2;  ///< [m]
  double band_max_m = 0.5;   ///< [m]
  double max_range_m = 4.0;  ///< [m] depth samples farther along the ray are not used
  /// [count] a cell is occupied when at least this many surface samples fell in it and they
  /// outnumber the rays that passed through it.
  int min_hits = 1;
};

/// The correlative search of a local plan in the map's plan (ScanSearch).
struct ScanSearchOptions {
  double yaw_step_deg = 1.0;  ///< [deg] rotations tried: 360 / step
  /// [count] levels of the branch-and-bound pyramid above the full resolution (a top-level
  /// node covers 2^levels cells per side).
  int pyramid_levels = 6;
  /// Alignments whose obstacle score is within this fraction of the best one are candidates:
  /// each distinct place among them is then judged by its agreement (score minus the
  /// free-space conflicts): a wrong place can cover more obstacles than the true one when the
  /// part sees the backs of things the map saw from the front, but it contradicts the map's
  /// free space more.
  double candidate_margin = 0.1;  ///< [fraction]
  /// [points] agreement lost per compared cell in conflict (an obstacle on an obstacle: 2).
  /// 0 (default): places ranked by score. 1 with candidate_margin 0.5 joined the slow profiles'
  /// reversed runs sooner and closer, but also twin rooms 4 m off (doc/maps.md).
  double conflict_penalty = 0.0;
  /// Places whose agreement is within this fraction of the best one's are kept: more than one
  /// is an ambiguity.
  double hypothesis_margin = 0.1;  ///< [fraction]
  /// Two hypotheses are distinct places when their alignments put the local plan's centre this
  /// far apart, or turn it by this much.
  double place_separation_m = 0.5;     ///< [m]
  double place_separation_deg = 20.0;  ///< [deg]
  /// [fraction] of the local occupied cells that must land on the map's occupied cells (or next
  /// to them: half credit) for a hypothesis to count.
  double min_overlap_fraction = 0.3;
  /// [fraction] of the compared cells whose free space conflicts (local obstacles in the map's
  /// free space, local free space on the map's obstacles) above which a hypothesis is refused.
  double max_conflict_fraction = 0.05;
  /// [count] candidate places evaluated at most; when more were found, those left out (lower
  /// obstacle scores) must lie outside the margin of the best agreement, or it is ambiguous.
  int max_hypotheses = 16;
};

struct RelocOptions {
  bool enable = true;  ///< runs with --load-map search the map geometrically too
  PlanGridOptions grid;
  ScanSearchOptions search;
  /// [m] path length of the part's latest keyframes that make the local plan.
  double submap_path_m = 3.0;
  /// [count] occupied cells the local plan needs before it is searched.
  int submap_min_occupied_cells = 80;
  /// [m] when the latest submap_path_m have fewer obstacle cells than that, older keyframes
  /// are added (up to this path) until the plan has them: thin structure (walls along the
  /// path, little furniture) gets a longer submap instead of no search. At most submap_path_m
  /// disables it.
  double submap_max_path_m = 6.0;
  double attempt_interval_m = 0.25;  ///< [m] path between two searches of one part
  /// [count] the result of a search started at loop keyframe k is taken at keyframe k + this
  /// (offline: a defined point, so threaded and sequential runs agree; live: when ready).
  int result_lag_keyframes = 3;
  /// A fit is only used once confirm_fits fits (the last started at least confirm_distance_m
  /// of path after the first) put the part at the same place within these bounds.
  int confirm_fits = 3;                       ///< [count] (2 = one confirmation)
  double confirm_distance_m = 0.75;           ///< [m]
  double confirm_max_disagreement_m = 0.10;   ///< [m]
  double confirm_max_disagreement_deg = 2.0;  ///< [deg]
  /// The join uses the mean of the agreeing fits (true) or the last of them (false): single
  /// fits scatter by centimetres and up to a degree.
  bool confirm_join_mean = false;
  /// ICP refinement of a hypothesis on the 3-D depth samples (nearest neighbours within this
  /// distance, these many iterations).
  double refine_max_distance_m = 0.15;  ///< [m]
  /// [m] the refinement uses the depth samples within this of their camera (map and submap):
  /// the plans may use farther ones (grid.max_range_m: more structure to search), but their
  /// depth noise (growing with the square of the range) would pull a centimetre fit apart.
  double refine_max_range_m = 4.0;
  /// The refinement moves yaw, x and y too (true), or keeps the search's (plan resolution) and
  /// solves the height and its drift only (false).
  bool refine_horizontal = true;
  int refine_iterations = 15;  ///< [count] 0 = off
  /// [m] pairs farther apart than this weigh this / their distance (Huber): what the map saw
  /// differently (the backs of things; the odometry's height drifting a few centimetres within
  /// the submap on ramps, which a ramp's surface turns into a sideways push) must not drag the
  /// fit. 1e9 or more: plain least squares.
  double refine_huber_m = 0.01;
  /// [m per m] the refinement also solves the odometry's height drift along the submap's path
  /// (a sample s metres before the anchor raised by s x drift), with this prior sigma: on ramps
  /// the submap's height drifts a few centimetres over 3 m, and a ramp seen at the wrong height
  /// pushes a fit without it sideways. 0: off (4-DOF).
  double refine_height_drift_sigma_per_m = 0.02;
  /// [cos] an ICP pair counts only when the map surface's normal, facing the cameras that saw it
  /// in the map, has at least this cosine with the direction from the local sample to its
  /// camera: both saw the same face (a run driven the other way sees the backs of what the map
  /// saw). Samples failing it are left out of the pairs and of the pair fraction. -1: off.
  double refine_min_view_cos = -1.0;
  /// [deg] the refinement also solves a tilt of the submap (prior 0 +- this): its gravity is
  /// the odometry's, off by 1-5 deg for seconds after a tracked robot tips over a step, which
  /// at 3 m of depth misplaces the walls by several centimetres. 0: off.
  double refine_tilt_sigma_deg = 0.0;
  /// After the refinement at least this fraction of the local samples (thinned) must have a map
  /// neighbour, at this RMS distance along the map's normals at most; otherwise the fit fails.
  double refine_min_pair_fraction = 0.5;  ///< [fraction]
  double refine_max_rms_m = 0.06;         ///< [m]
  /// ... and the pairs' normals must pin both horizontal directions: the smaller eigenvalue of
  /// sum n_xy n_xy^T / trace at least this (0 .. 0.5; a lone wall lets the fit slide along it).
  double refine_min_horizontal_constraint = 0.05;  ///< [fraction]
  /// [count] cells of floor seen in both plans needed to find the height offset.
  int min_floor_cells = 20;
  /// The join: loop edges from the part's latest keyframes (at most this many) to the map
  /// keyframe nearest each (within join_max_distance_m of where the fit puts it).
  int join_keyframes = 6;            ///< [count]
  double join_max_distance_m = 1.5;  ///< [m]
  /// Tracking after the join (what a lidar localiser does): once the part is in the map's frame
  /// (a geometric or visual join), every track_interval_m of path its latest submap_path_m of
  /// depth is refined against the map's samples by the same ICP, started at the part's present
  /// map-frame pose (no search), and a fit passing the join's checks (pair fraction, RMS,
  /// horizontal constraint, the neighbourhood free-space check) adds loop edges from the part's
  /// latest track_keyframes keyframes to the nearest map keyframes (within join_max_distance_m),
  /// so the pose graph averages many fits instead of keeping the join's one. 0: off.
  double track_interval_m = 0.0;  ///< [m] (0.25 measured: doc/maps.md)
  /// A tracking fit that moves the newest keyframe farther than this, or turns it by more, from
  /// where the pose graph has it now is refused (it must not pull the run somewhere else).
  double track_max_correction_m = 0.10;   ///< [m]
  double track_max_correction_deg = 2.0;  ///< [deg]
  int track_keyframes = 3;                ///< [count] loop edges per tracking fit
  /// Sigmas of a tracking fit's loop edges (a geometric join's have the pose graph's
  /// loop_sigma_pos_m / loop_sigma_yaw_deg).
  double track_sigma_pos_m = 0.05;   ///< [m]
  double track_sigma_yaw_deg = 1.0;  ///< [deg]

  /// Reads and validates every [relocalise] key (ConfigError names file, key and range).
  static RelocOptions load(IniReader& ini);
};

}  // namespace rgbdi::reloc
