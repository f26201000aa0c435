#include "rgbdi/system/run_common.h"

#include <filesystem>
#include <fstream>

#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/output/summary_json.h"
#include "rgbdi/system/slam_outputs.h"

namespace rgbdi::system {
namespace fs = std::filesystem;

namespace {

/// Ground truth expressed in the estimate's frame (position + yaw alignment) for plot and scene.
Trajectory groundTruthInEstimateFrame(const Trajectory& gt, const RunEvaluation& ev) {
  Trajectory out;
  if (!ev.final_posyaw) return out;
  const Eigen::Isometry3d T_est_gt = ev.final_posyaw->alignment.rigid().inverse();
  for (const auto& g : gt) out.push_back(StampedPose::fromIsometry(g.t, T_est_gt * g.isometry()));
  return out;
}

}  // namespace

SystemConfig loadRunConfig(const std::string& path) {
  try {
    return SystemConfig::load(path);
  } catch (const ConfigError& e) {
    throw UserError(std::string("configuration error: ") + e.what());
  }
}

Trajectory readGroundTruth(const std::string& path) {
  if (path.empty()) return {};
  if (!fs::exists(path)) throw UserError(path + ": ground-truth file does not exist");
  try {
    return eval::readTum(path);
  } catch (const std::exception& e) {
    throw UserError(e.what());
  }
}

void prepareOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw UserError(dir + ": cannot create output directory: " + ec.message());
  const std::string probe = dir + "/.rgbdi_write_test";
  std::ofstream f(probe);
  if (!f) throw UserError(dir + ": output directory is not writable");
  f.close();
  fs::remove(probe, ec);
}

nlohmann::json finishRun(const SlamSystem& system, RunInfo run,
                         const io::StreamDiagnostics& diagnostics, const Trajectory& gt,
                         const RunOutputOptions& options, const nlohmann::json& extra,
                         std::ostream& log) {
  run.stream_diagnostics = nlohmann::json::parse(diagnostics.toJson());
  // Every stream problem once on the console (the progress line has been ended).
  for (const std::string& line : io::streamProblemLines(diagnostics))
    log << "rgbdi-slam: " << line << "\n";

  RunEvaluation evaluation;
  if (!gt.empty()) evaluation = evaluateRun(system, gt);
  const Trajectory gt_in_est = groundTruthInEstimateFrame(gt, evaluation);
  nlohmann::json outputs = writeSlamOutputs(
      system, options.out_dir, gt_in_est.empty() ? nullptr : &gt_in_est, options.save_simplemap);
  const std::string summary_path = options.out_dir + "/summary.json";
  outputs["summary"] = summary_path;
  nlohmann::json summary = slamSummary(system, run, evaluation, outputs);
  for (const auto& [key, value] : extra.items()) summary[key] = value;
  output::writeSummaryJson(summary_path, summary);
  log << formatRunReport(summary, evaluation, options.gt_path);
  if (system.frames().empty())
    log << "rgbdi-slam: no pose was estimated: "
        << (run.frames == 0 ? "the input has no colour image"
                            : "the odometry never initialised (summary.json: resets, "
                              "stream_diagnostics)")
        << "\n";
  return summary;
}

}  // namespace rgbdi::system
