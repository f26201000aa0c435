// [convert]: how rawlog-convert pairs, merges, orders and scales the data it converts (ROS1 bags
// and TUM RGB-D folders). Command-line options of rawlog-convert override these values.
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::bag {

struct ConvertOptions {
  double pair_tolerance_s =
      0.02;  ///< [s] colour and depth stamps at most this far apart form a frame
  double max_wait_s =
      0.5;  ///< [s] an image or gyro sample waits at most this much newer data for its partner
  double reorder_window_s = 0.5;  ///< [s] output is re-ordered by stamp within this window
  double max_accel_gap_s = 0.05;  ///< [s] no accelerometer interpolation across larger gaps
  double integer_depth_unit_m =
      1e-3;                          ///< [m] unit of 16UC1/mono16 depth when the input does not say
  double float_depth_unit_m = 1e-3;  ///< [m] unit in which 32FC1 (metre) depth is stored
  double tum_depth_factor = 5000.0;  ///< [units/m] depth PNG scale of TUM RGB-D folders
  bool require_colour = false;       ///< [bool] drop depth images without a colour partner
  int max_listed_issues = 10;        ///< [count] messages listed per kind in the report
  double progress_interval_s = 1.0;  ///< [s] wall-clock period of the progress line

  static ConvertOptions load(IniReader& ini);
};

}  // namespace rgbdi::bag
