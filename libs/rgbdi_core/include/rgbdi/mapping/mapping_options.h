// Options of the mapping stage: the [mapping] section of the configuration (point octree,
// occupancy OctoMap, exported scene and trajectory plot).
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::mapping {

/// Appearance of trajectory.png.
struct TrajectoryPlotOptions {
  int panel_px = 600;  ///< [px] side of each of the two square view panels
  /// [s] an estimated pose is compared with the ground-truth pose nearest in time when they are
  /// at most this far apart (for the error colouring).
  double max_time_diff_s = 0.02;
};

/// Appearance of scene.3Dscene.
struct SceneOptions {
  double keyframe_axis_m = 0.1;  ///< [m] length of the axes drawn at each keyframe
};

/// Point-map and occupancy-map parameters. Defaults equal share/config.ini.
struct MappingOptions {
  // --- depth subsampling per keyframe (paper section 4.5) ---
  int grid_step_px = 10;     ///< [px] sampling step in both image directions
  int u_min_px = 40;         ///< [px] first sampled column (depth image)
  int u_max_px = 590;        ///< [px] last sampled column (clipped to the image)
  int v_min_px = 10;         ///< [px] first sampled row
  int v_max_px = 460;        ///< [px] last sampled row (clipped to the image)
  double depth_min_m = 0.3;  ///< [m] a point is kept when depth_min_m < z < depth_max_m
  double depth_max_m = 6.0;  ///< [m]

  // --- point octree ---
  double octree_resolution_m = 0.02;  ///< [m] leaf size
  int max_points_per_leaf = 5;  ///< [count] later points falling into a full leaf are rejected
  /// [count] rebuild() drops a leaf when fewer points than this lie within about three leaves of
  /// it (see PointMap::rebuild): isolated points go, surfaces seen by a single keyframe (whose
  /// grid spacing exceeds the leaf size beyond about 1 m) stay
  int min_points_per_leaf_rebuild = 3;
  /// A map correction moves a keyframe (and rebuilds the map) only when the correction shifts it
  /// by at least this much or turns it by at least correction_min_rotation_deg.
  double correction_min_shift_m = 0.01;      ///< [m]
  double correction_min_rotation_deg = 0.5;  ///< [deg]

  // --- redundant keyframes (see viewpoint_index.h) ---
  /// [m] a keyframe adds points only when no keyframe already in the map is closer than this
  /// and turned by less than view_update_angle_deg; 0 = every keyframe adds points
  double view_update_distance_m = 0.15;
  double view_update_angle_deg = 15.0;  ///< [deg]

  // --- occupancy OctoMap (map.bt; built when [output] write_octomap is set) ---
  double occupancy_resolution_m = 0.05;  ///< [m] leaf size of the occupancy OctoMap
  /// [count] rays are cast through every n-th row and column of the sampling grid (ray casting
  /// is the expensive part of mapping; 2 casts a quarter of the grid).
  int occupancy_grid_stride = 2;
  double occupancy_prob_hit = 0.7;   ///< [unitless] probability of an endpoint being occupied
  double occupancy_prob_miss = 0.4;  ///< [unitless] probability of a traversed cell being occupied

  TrajectoryPlotOptions plot;
  SceneOptions scene;

  /// Throws ConfigError when a value is outside its range or inconsistent with another one.
  void validate() const;
  /// Reads [mapping]; missing keys keep the defaults above.
  static MappingOptions load(IniReader& ini);
};

}  // namespace rgbdi::mapping
