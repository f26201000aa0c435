#include "rgbdi/system/slam_runner.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/output/summary_json.h"
#include "rgbdi/system/progress_reporter.h"
#include "rgbdi/system/slam_outputs.h"
#include "rgbdi/system/slam_summary.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {
namespace fs = std::filesystem;

namespace {

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

SystemConfig loadConfig(const std::string& path) {
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

/// Ground truth expressed in the estimate's frame (position + yaw alignment) for plot and scene.
Trajectory groundTruthInEstimateFrame(const Trajectory& gt, const RunEvaluation& ev) {
  Trajectory out;
  if (!ev.final_posyaw) return out;
  const Eigen::Isometry3d T_est_gt = ev.final_posyaw->alignment.rigid().inverse();
  for (const auto& g : gt) out.push_back(StampedPose::fromIsometry(g.t, T_est_gt * g.isometry()));
  return out;
}

}  // namespace

nlohmann::json runSlam(const SlamRunOptions& opt, std::ostream& log) {
  if (opt.input.empty()) throw UserError("no input given (--input SEQ.rawlog)");
  if (!fs::exists(opt.input)) throw UserError(opt.input + ": input file does not exist");
  SystemConfig cfg = loadConfig(opt.config_path);
  if (opt.no_loop) cfg.loop.enable = false;
  const Trajectory gt = readGroundTruth(opt.gt_path);  // before the run: bad files fail fast
  prepareOutputDir(opt.out_dir);

  std::unique_ptr<io::RawlogSource> source;
  try {
    source = std::make_unique<io::RawlogSource>(opt.input, cfg.streamConfig());
  } catch (const std::exception& e) {
    throw UserError(e.what());
  }
  source->setMinLoggingLevel(mrpt::system::LVL_ERROR);  // warnings go into the diagnostics

  SlamSystemOptions so;
  so.use_depth = !opt.no_depth;
  so.threaded = opt.threaded;
  so.keep_observations = opt.save_simplemap;
  SlamSystem system(cfg, so);
  ProgressReporter progress(system, log, opt.quiet, cfg.output.progress_interval_s,
                            [&] { return source->progress(); });

  RunInfo run;
  run.input = opt.input;
  run.no_depth = opt.no_depth;
  const auto wall0 = std::chrono::steady_clock::now();
  try {
    source->pump(progress, opt.stop);
  } catch (const io::RawlogError& e) {
    run.read_error = e.what();  // everything before the damage was processed
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  run.interrupted = opt.stop && opt.stop->load();
  run.stream_t0 = progress.firstStamp();
  run.stream_t_last = progress.lastStamp();
  run.frames = progress.framesSeen();
  run.stream_diagnostics = nlohmann::json::parse(source->diagnostics().toJson());
  // Every stream problem once on the console (the progress line has been ended).
  for (const std::string& line : io::streamProblemLines(source->diagnostics()))
    log << "rgbdi-slam: " << line << "\n";

  RunEvaluation evaluation;
  if (!gt.empty()) evaluation = evaluateRun(system, gt);
  const Trajectory gt_in_est = groundTruthInEstimateFrame(gt, evaluation);
  nlohmann::json outputs = writeSlamOutputs(
      system, opt.out_dir, gt_in_est.empty() ? nullptr : &gt_in_est, opt.save_simplemap);
  const std::string summary_path = opt.out_dir + "/summary.json";
  outputs["summary"] = summary_path;
  nlohmann::json summary = slamSummary(system, run, evaluation, outputs);
  output::writeSummaryJson(summary_path, summary);
  log << formatRunReport(summary, evaluation, opt.gt_path);
  if (system.frames().empty())
    log << "rgbdi-slam: no pose was estimated: "
        << (run.frames == 0 ? "the input has no colour image"
                            : "the odometry never initialised (summary.json: resets, "
                              "stream_diagnostics)")
        << "\n";
  return summary;
}

}  // namespace rgbdi::system
