// Benchmark of the whole odometry on a simulated sequence streamed in-process (no disk):
// per-stage timings, throughput and accuracy.
//   bench_vio [--profile NAME] [--duration S] [--fps N] [--seed N] [--no-depth] [--time-offset S]
//             [--set SECTION.KEY=VALUE ...]   (overrides of the generated slam config; [sim]
//             keys override the simulator's options, e.g. --set sim.depth_sigma_coeff=0)
//             [--trajectory FILE]   (writes the optimised body trajectory, TUM, to compare runs)
#include <chrono>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/output/tum_writer.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/system_config.h"
#include "rgbdi/system/vio_system.h"

using namespace rgbdi;

int main(int argc, char** argv) {
  std::string profile = "wheeled_circle";
  double duration = 0.0, fps = 30.0;
  std::uint64_t seed = 1;
  bool no_depth = false;
  bool verbose = false;
  double time_offset = 0.0;
  std::string trajectory_path;
  std::map<std::string, std::map<std::string, std::string>> overrides;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--profile")
      profile = next();
    else if (a == "--duration")
      duration = std::stod(next());
    else if (a == "--fps")
      fps = std::stod(next());
    else if (a == "--seed")
      seed = std::stoull(next());
    else if (a == "--no-depth")
      no_depth = true;
    else if (a == "--verbose")
      verbose = true;
    else if (a == "--time-offset")
      time_offset = std::stod(next());
    else if (a == "--trajectory")
      trajectory_path = next();
    else if (a == "--set") {
      const std::string kv = next();
      const auto dot = kv.find('.'), eq = kv.find('=');
      if (dot == std::string::npos || eq == std::string::npos || eq < dot) {
        std::cerr << "--set expects SECTION.KEY=VALUE\n";
        return 2;
      }
      overrides[kv.substr(0, dot)][kv.substr(dot + 1, eq - dot - 1)] = kv.substr(eq + 1);
    } else {
      std::cerr << "usage: bench_vio [--profile NAME] [--duration S] [--fps N] [--seed N] "
                   "[--no-depth] [--set SECTION.KEY=VALUE] [--trajectory FILE]\n";
      return 2;
    }
  }
  // [sim] overrides shape the generated sequence (noise, variant, ...); the others the slam config.
  std::string sim_text;
  if (const auto it = overrides.find("sim"); it != overrides.end()) {
    sim_text = "[sim]\n";
    for (const auto& [k, v] : it->second) sim_text += k + " = " + v + "\n";
    overrides.erase(it);
  }
  auto sim_ini = IniReader::fromText(sim_text, "bench_vio --set sim.*");
  sim::SimOptions so = sim::SimOptions::load(sim_ini);
  so.profile.kind = sim::parseProfileKind(profile);
  so.profile.duration_s = duration;
  so.fps = fps;
  so.seed = seed;
  so.time_offset_s = time_offset;
  sim::SimulatedSequence seq(so);

  // The slam configuration a user would have for this sequence, plus overrides.
  std::string cfg_text = sim::slamConfigText(seq);
  for (const auto& [sec, kv] : overrides) {
    cfg_text += "\n[" + sec + "]\n";
    for (const auto& [k, v] : kv) cfg_text += k + " = " + v + "\n";
  }
  auto ini = IniReader::fromText(cfg_text, "bench config");
  const system::SystemConfig cfg = system::SystemConfig::load(ini);

  system::VioSystem vio(cfg, !no_depth);
  if (verbose) vio.estimator().setMinLoggingLevel(mrpt::system::LVL_DEBUG);
  double used = 0, verified = 0;  // features per estimator update
  int updates = 0;
  vio.setFrameCallback([&](const estimator::FrameEstimate& e, const RgbdFrame&) {
    if (e.n_features_used <= 0) return;
    used += e.n_features_used;
    verified += e.n_depth_verified;
    ++updates;
  });
  const auto t0 = std::chrono::steady_clock::now();
  seq.pump(vio);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  const auto& tm = vio.timings();
  const auto& st = vio.estimatorStats();
  const double nt = std::max(1, tm.frames_tracked), ne = std::max(1, tm.frames_estimated);
  std::cout << std::fixed << std::setprecision(3);
  std::cout << "profile " << profile << (no_depth ? " (--no-depth)" : "") << ", "
            << seq.frameCount() << " frames at " << fps << " Hz, " << seq.duration() << " s\n";
  std::cout << "per frame [ms]: tracking " << tm.tracking_ms / nt << ", pre-integration "
            << tm.preintegration_ms / ne << ", optimisation " << tm.optimisation_ms / ne
            << ", marginalisation " << tm.marginalisation_ms / ne << "\n";
  std::cout << "wall " << wall << " s incl. rendering; odometry only "
            << (tm.tracking_ms + tm.optimisation_ms + tm.marginalisation_ms +
                tm.preintegration_ms) /
                   1000.0
            << " s -> "
            << nt / ((tm.tracking_ms + tm.optimisation_ms + tm.marginalisation_ms +
                      tm.preintegration_ms) /
                     1000.0)
            << " frames/s\n";
  std::cout << "resets " << st.resets << ", first pose at "
            << (st.first_pose_t_image - seq.frameStamp(0)) << " s, time offset "
            << 1000.0 * vio.estimator().timeOffset() << " ms\n";
  std::cout << "estimator updates " << st.optimisations << ", solver iterations per update "
            << (st.optimisations > 0 ? double(st.solver_iterations) / st.optimisations : 0.0)
            << ", stopped at their iteration limit " << st.solver_iterations_capped
            << ", single-step updates (non_keyframe_update) " << st.single_step_updates
            << ", factorisations retried with more damping " << st.solver_factorisation_retries
            << "\n";
  if (updates > 0)
    std::cout << "features per update: " << used / updates << " used, " << verified / updates
              << " depth-verified\n";
  if (!trajectory_path.empty())
    output::writeTum(trajectory_path, vio.trajectoryBody(), "body (IMU) frame in the world frame");
  const Trajectory gt = seq.bodyTrajectory();
  for (auto mode : {eval::AlignMode::PosYaw, eval::AlignMode::Sim3}) {
    eval::EvalOptions eo;
    eo.align = mode;
    try {
      const auto r = eval::evaluate(gt, vio.trajectoryBody(), eo);
      std::cout << eval::alignModeName(mode) << ": ATE rmse " << std::setprecision(4) << r.ate.rmse
                << " m, max " << r.ate.max << " m, scale " << std::setprecision(5)
                << r.alignment.scale << ", coverage " << std::setprecision(4) << r.coverage.coverage
                << ", RPE(1s) " << r.rpe.trans_rmse_m << " m\n";
    } catch (const std::exception& e) {
      std::cout << "evaluation failed: " << e.what() << "\n";
    }
  }
  return 0;
}
