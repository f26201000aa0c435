// One offline rgbdi-slam run: read a rawlog into the SLAM system, write every output, evaluate
// against ground truth when given. Everything the rgbdi-slam app does apart from parsing
// arguments, so tests and benchmarks run exactly what users run.
#pragma once

#include <atomic>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "rgbdi/system/run_common.h"

namespace rgbdi::system {

struct SlamRunOptions {
  std::string input;        ///< rawlog path
  std::string out_dir;      ///< created if missing
  std::string config_path;  ///< empty = built-in defaults (share/config.ini values)
  std::string gt_path;      ///< optional ground truth (TUM); body frame unless gt_frame = "camera"
  bool no_depth = false;    ///< monocular baseline
  bool no_loop = false;     ///< loop closure off (overrides [loop] enable)
  bool no_wheels = false;   ///< wheel odometry ignored (overrides [wheel] enable)
  bool quiet = false;       ///< no progress line
  /// The log is a terminal: the progress line is redrawn in place; otherwise one line per tenth
  /// of the stream (ProgressReporter::setInteractive).
  bool progress_interactive = true;
  bool save_simplemap = false;  ///< also write keyframes.simplemap (keyframe observations + poses)
  bool threaded = true;  ///< stages on their own threads (false: sequential, identical outputs)
  MapRunOptions map;     ///< --load-map, --localize-only, --no-save-map
  const std::atomic<bool>* stop = nullptr;  ///< set by Ctrl-C: stop reading, write what we have
};

/// Runs and writes DIR/trajectory{,_online,_odometry}{,_cam}.tum, keyframes.tum,
/// pose_graph.graph, map.ply, map.bt, map.pointsmap, scene.3Dscene, trajectory.png and
/// summary.json (with the evaluation when ground truth is given).
/// Returns the summary. `log` receives the human-readable report and the progress line.
nlohmann::json runSlam(const SlamRunOptions& opt, std::ostream& log);

}  // namespace rgbdi::system
