#include "rgbdi/system/slam_runner.h"

#include <chrono>
#include <filesystem>

#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/system/progress_reporter.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {
namespace fs = std::filesystem;

nlohmann::json runSlam(const SlamRunOptions& opt, std::ostream& log) {
  if (opt.input.empty()) throw UserError("no input given (--input SEQ.rawlog)");
  if (!fs::exists(opt.input)) throw UserError(opt.input + ": input file does not exist");
  SystemConfig cfg = loadRunConfig(opt.config_path);
  if (opt.no_loop) cfg.loop.enable = false;
  if (opt.no_wheels) cfg.estimator.wheel.enable = false;
  if (cfg.estimator.max_solver_time_s > 0.0) {
    // A wall-clock budget makes the result depend on the machine's load: offline runs stay
    // deterministic (same input + config = same output), so it applies to --live only.
    log << "rgbdi-slam: [estimator] max_solver_time_s = " << cfg.estimator.max_solver_time_s
        << " s is a live-mode budget; ignored for --input (the solver runs to its iteration "
           "limit)\n";
    cfg.estimator.max_solver_time_s = 0.0;
  }
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
  so.map = loadRunMap(opt.map, cfg);
  so.localize_only = opt.map.localize_only;
  SlamSystem system(cfg, so);
  ProgressReporter progress(system, log, opt.quiet, cfg.output.progress_interval_s,
                            [&] { return source->progress(); });
  progress.setInteractive(opt.progress_interactive);

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
  return finishRun(system, run, source->diagnostics(), gt,
                   RunOutputOptions{opt.out_dir, opt.gt_path, opt.save_simplemap, opt.map},
                   nlohmann::json::object(), log);
}

}  // namespace rgbdi::system
