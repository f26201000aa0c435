// Options of the navigation maps (section [navmap] of share/config.ini, doc/navigation-maps.md):
// the grid, what the robot can drive over (its footprint, slope, step and clearance limits) and
// when a live run rewrites the maps.
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::navmap {

struct NavMapOptions {
  bool enable = true;         ///< write the navigation maps (navmap.*) at the end of a run
  double cell_size_m = 0.05;  ///< [m] side of a grid cell
  double range_m =
      5.0;  ///< [m] cells farther than this horizontally from the path are left unknown
  int min_points_per_cell =
      3;  ///< [count] points of the lowest surface a cell needs for a ground height
  /// [m] points within this of the cell's lowest surface (its min_points_per_cell-th lowest
  /// point) are ground points: their mean is the ground height
  double ground_band_m = 0.04;
  int min_obstacle_points =
      2;  ///< [count] points in the obstacle band that make a cell an obstacle
  double footprint_radius_m =
      0.2;  ///< [m] radius of the robot's footprint (cells it drove over are free)
  double max_slope_deg = 20.0;  ///< [deg] steepest ground the robot drives on
  /// [m] highest step the robot climbs or descends; also the bottom of the obstacle band (a
  /// point higher than this above the ground is an obstacle)
  double max_step_m = 0.1;
  /// [m] top of the obstacle band: points higher than this above the ground are overhangs the
  /// robot passes under (table tops, ceilings)
  double clearance_height_m = 0.5;
  /// [m] RMS deviation of the ground from its local plane that makes traversability 0
  double max_roughness_m = 0.05;
  /// [m] the ground under a path position is the median ground of the cells within this radius
  /// below it; the median of the path's height above it over the path gives the robot's ground
  double path_ground_radius_m = 1.0;
  /// [0..1] the ground under a path position is the lowest height band (max_step_m deep) holding
  /// at least this fraction of those cells, not their median: box and table tops beside a
  /// hand-held camera whose floor was rarely seen do not lift it; 1 = the median of them all
  double path_ground_min_fraction = 0.1;
  /// [m] map points the camera saw farther than this are left out: depth noise grows with the
  /// square of the distance, and the points of a wall seen from far spill into the floor cells
  /// in front of it as obstacles
  double max_depth_m = 3.5;
  /// [s] live runs rewrite the maps at this wall-clock period (and after each loop correction);
  /// 0 = at the end only
  double refresh_interval_s = 10.0;
  /// [m] a cell whose points rise at least this far above its lowest surface (within
  /// max_step_m of it) while that surface lies drop_face_min_depth_m or more below the robot's
  /// ground is the top of a face going down (a hole's or a drop's wall seen only a few
  /// centimetres down), not floor: a step edge, and so are its neighbours standing that far
  /// above it (the rim). A floor shows points at one height. 0 = off
  double drop_face_min_rise_m = 0.03;
  /// [m] how far below the robot's ground (the reference ground of the cell) the lowest surface
  /// of such a face must lie; a riser going up from the floor (its lowest surface the floor)
  /// is not a drop
  double drop_face_min_depth_m = 0.02;

  /// Throws ConfigError naming the key when a value is outside its range or inconsistent.
  void validate() const;
  /// Reads [navmap]; missing keys keep the defaults above.
  static NavMapOptions load(IniReader& ini);
};

}  // namespace rgbdi::navmap
