// summary.json of a SLAM run and the human-readable report printed at its end, built from a
// finished SlamSystem and what the runner knows of the run (input, stream span, wall time).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

struct RunInfo {
  std::string input;
  bool no_depth = false;
  bool interrupted = false;
  std::string read_error;                       ///< empty when the input was read to its end
  double stream_t0 = 0.0, stream_t_last = 0.0;  ///< [s] first and last stamp (NaN: none)
  std::size_t frames = 0;                       ///< images fed
  double wall_s = 0.0;
  nlohmann::json stream_diagnostics;
};

/// The three trajectories of a run evaluated against ground truth (position + yaw alignment;
/// Sim(3) of the final one for the scale).
struct RunEvaluation {
  std::optional<eval::EvalResult> final_posyaw, final_sim3, online, odometry;
  std::string error;  ///< why the evaluation failed (empty otherwise)
};

/// Evaluates final, online and odometry trajectories; failures go into `error`.
RunEvaluation evaluateRun(const SlamSystem& system, const Trajectory& gt);

/// The "loop" object of summary.json: counts (queried, candidates, rejected per reason,
/// accepted, rolled back), timings, segments and their final drift correction.
nlohmann::json loopSummary(const SlamSystem& system);

nlohmann::json slamSummary(const SlamSystem& system, const RunInfo& run,
                           const RunEvaluation& evaluation, const nlohmann::json& outputs);

/// Accuracy lines (the three trajectories side by side) and the closing lines of the report.
std::string formatRunReport(const nlohmann::json& summary, const RunEvaluation& evaluation,
                            const std::string& gt_path);

}  // namespace rgbdi::system
