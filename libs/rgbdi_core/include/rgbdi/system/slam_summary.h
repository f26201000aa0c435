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
  std::string map_loaded_from;  ///< --load-map directory (empty: none)
  std::string map_saved_to;     ///< directory the run's map was saved to (empty: not saved)
  std::string map_save_note;    ///< why it was not saved, or what was left out
};

/// The three trajectories of a run evaluated against ground truth (position + yaw alignment;
/// Sim(3) of the final one for the scale).
struct RunEvaluation {
  std::optional<eval::EvalResult> final_posyaw, final_sim3, online, odometry;
  /// With a loaded map that knows its ground-truth alignment: final and online trajectories
  /// mapped through it, no alignment of their own (the ATE in the map's frame).
  std::optional<eval::EvalResult> final_in_map, online_in_map;
  std::string error;  ///< why the evaluation failed (empty otherwise)
};

/// Evaluates final, online and odometry trajectories; failures go into `error`.
RunEvaluation evaluateRun(const SlamSystem& system, const Trajectory& gt);

/// The "loop" object of summary.json: counts (queried, candidates, rejected per reason,
/// accepted, rolled back), timings, segments and their final drift correction.
nlohmann::json loopSummary(const SlamSystem& system);

/// The "map_session" object of summary.json: the loaded map and its mode, the run's state in it,
/// when it relocalised (seconds after the stream start), the joins, and where the map was saved.
nlohmann::json mapSessionSummary(const SlamSystem& system, const RunInfo& run);

nlohmann::json slamSummary(const SlamSystem& system, const RunInfo& run,
                           const RunEvaluation& evaluation, const nlohmann::json& outputs);

/// The three most frequent reasons of summary.json's "initialisation_waits" for the console, as
/// "reason (N frames)" joined by "; " (most frequent first, equal counts in text order).
std::string initWaitsLine(const nlohmann::json& waits);

/// Why a run estimated no pose, for the console and summary.json "no_pose_reason": the first
/// missing ingredient (no colour+depth frame read and why, no IMU sample, IMU and frames at
/// different times) before the reasons the odometry waited (`waits`, "initialisation_waits").
/// Reads run.frames, run.interrupted and run.stream_diagnostics.
std::string noPoseReason(const RunInfo& run, const nlohmann::json& waits);

/// Accuracy lines (the three trajectories side by side) and the closing lines of the report.
std::string formatRunReport(const nlohmann::json& summary, const RunEvaluation& evaluation,
                            const std::string& gt_path);

}  // namespace rgbdi::system
