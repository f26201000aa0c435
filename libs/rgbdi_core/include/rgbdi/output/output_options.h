// Options of section [output] of share/config.ini: which result files a run writes.
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::output {

struct OutputOptions {
  bool write_ply = true;             ///< map.ply
  bool write_octomap = true;         ///< map.bt
  bool write_scene = true;           ///< scene.3Dscene
  bool write_plot = true;            ///< trajectory.png
  double progress_interval_s = 1.0;  ///< [s] wall-clock period of the progress line on stderr
  /// Uncertainty given to odometry edges of pose_graph.graph (between consecutive keyframes).
  double graph_translation_sigma_m = 0.01;  ///< [m]
  double graph_rotation_sigma_rad = 0.005;  ///< [rad]

  static OutputOptions load(IniReader& ini);
};

}  // namespace rgbdi::output
