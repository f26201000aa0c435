#include "rgbdi/system/run_common.h"

#include <filesystem>
#include <fstream>

#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/loop/loop_features.h"
#include "rgbdi/map/map_directory.h"
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
    throw RunConfigError(std::string("configuration error: ") + e.what());
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

std::shared_ptr<const map::MapData> loadRunMap(const MapRunOptions& options,
                                               const SystemConfig& cfg) {
  if (options.load_dir.empty()) {
    if (options.localize_only) throw UserError("--localize-only needs --load-map DIR/map");
    return nullptr;
  }
  if (!cfg.loop.enable)
    throw UserError(
        "--load-map needs loop closure (relocalisation is a loop to the map): "
        "drop --no-loop / set [loop] enable = true");
  try {
    auto m = std::make_shared<const map::MapData>(map::loadMap(options.load_dir));
    // The colour camera of the configuration; a stream that brings its own intrinsics is
    // checked again when the first keyframe arrives.
    if (cfg.camera.camera.valid())
      map::checkCompatible(m->manifest, cfg.camera.camera, cfg.extrinsic.T_body_cam,
                           loop::kLoopDescriptorType, options.load_dir);
    return m;
  } catch (const map::MapError& e) {
    throw UserError(e.what());
  }
}

namespace {
/// Saves the run's map as DIR/map/ (after endOfStream: every stage thread has stopped).
void saveRunMap(const SlamSystem& system, const RunOutputOptions& options,
                const RunEvaluation& evaluation, RunInfo& run, std::ostream& log) {
  if (!options.map.save) {
    run.map_save_note = "not saved (--no-save-map)";
    return;
  }
  if (options.map.localize_only) {
    run.map_save_note = "not saved: --localize-only leaves the loaded map as it was";
    return;
  }
  if (!system.loopCloser()) {
    run.map_save_note = "not saved: loop closure did not run (a map needs its place keyframes)";
    return;
  }
  std::size_t dropped = 0;
  map::MapView m = system.mapView(&dropped);
  if (const map::MapData* loaded = system.loadedMap()) {
    m.manifest.has_groundtruth_alignment = loaded->manifest.has_groundtruth_alignment;
    m.manifest.T_groundtruth_world = loaded->manifest.T_groundtruth_world;
  } else if (evaluation.final_posyaw) {
    m.manifest.has_groundtruth_alignment = true;
    m.manifest.T_groundtruth_world = evaluation.final_posyaw->alignment.rigid();
  }
  map::MapExtras extras;
  extras.point_map = &system.mapper().pointMap();
  extras.occupancy = system.mapper().occupancy();
  const std::string dir = options.out_dir + "/map";
  try {
    map::saveMap(dir, m, extras);
  } catch (const map::MapError& e) {
    run.map_save_note = std::string("not saved: ") + e.what();
    log << "rgbdi-slam: map " << run.map_save_note << "\n";
    return;
  }
  run.map_saved_to = dir;
  if (dropped > 0)
    run.map_save_note = std::to_string(dropped) +
                        " keyframes of segments never joined to the map's frame were left out";
}
}  // namespace

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
  const double output_t0 = threadCpuSeconds();
  saveRunMap(system, options, evaluation, run, log);
  run.map_loaded_from = options.map.load_dir;
  const Trajectory gt_in_est = groundTruthInEstimateFrame(gt, evaluation);
  // Without a pose every trajectory, map and plot would be an empty file: only summary.json,
  // which says why, is written.
  const bool no_pose = system.frames().empty();
  nlohmann::json navmap_summary;
  nlohmann::json outputs =
      no_pose ? nlohmann::json::object()
              : writeSlamOutputs(system, options.out_dir, gt_in_est.empty() ? nullptr : &gt_in_est,
                                 options.save_simplemap, &navmap_summary);
  // CPU time of writing the map directory and every output file (summary.json itself excluded).
  const double output_ms = 1e3 * (threadCpuSeconds() - output_t0);
  const std::string summary_path = options.out_dir + "/summary.json";
  outputs["summary"] = summary_path;
  nlohmann::json summary = slamSummary(system, run, evaluation, outputs);
  summary["timing_ms_total"] = {{"output", output_ms}};
  if (!navmap_summary.is_null()) summary["navmap"] = navmap_summary;
  if (no_pose) summary["no_pose_reason"] = noPoseReason(run, summary["initialisation_waits"]);
  for (const auto& [key, value] : extra.items()) summary[key] = value;
  output::writeSummaryJson(summary_path, summary);
  log << formatRunReport(summary, evaluation, options.gt_path);
  if (no_pose)
    log << "rgbdi-slam: no pose was estimated: " << summary["no_pose_reason"].get<std::string>()
        << "\n";
  return summary;
}

}  // namespace rgbdi::system
