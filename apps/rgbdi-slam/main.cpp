// rgbdi-slam: RGB-D-inertial SLAM (odometry, loop closure, mapping) on an MRPT rawlog.
#include <atomic>
#include <csignal>
#include <cstring>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "rgbdi/system/slam_runner.h"

namespace {

std::atomic<bool> g_stop{false};

void onSignal(int) { g_stop.store(true); }

void usage(std::ostream& os) {
  os << "Usage: rgbdi-slam --input SEQ.rawlog --out DIR [--config FILE] [--gt GT.tum]\n"
        "                  [--no-depth] [--no-loop] [--save-simplemap] [--sequential]\n"
        "                  [--quiet]\n"
        "  --input FILE   MRPT rawlog with CObservation3DRangeScan (colour+depth) and "
        "CObservationIMU\n"
        "  --out DIR      output directory (created): trajectory.tum (best estimate), "
        "trajectory_online.tum,\n"
        "                 trajectory_odometry.tum (+ _cam twins), maps, pose graph, summary.json\n"
        "  --config FILE  rgbdi INI configuration (default: built-in values = share/config.ini)\n"
        "  --gt FILE      ground truth (TUM, body/IMU frame): prints and stores rgbdi-eval "
        "figures\n"
        "  --no-depth     monocular-inertial baseline: ignore depth\n"
        "  --no-loop      no loop closure (odometry and mapping only; [loop] enable = false)\n"
        "  --save-simplemap  also write keyframes.simplemap (keyframe observations + poses)\n"
        "  --sequential   run every stage on one thread (same outputs, for debugging)\n"
        "  --quiet        no progress line\n"
        "Ctrl-C stops reading and still writes all outputs for the part processed.\n"
        "Exit status: 0 ok, 1 error (nothing usable), 2 usage, 3 damaged input (outputs of the\n"
        "part read are written), 130 interrupted.\n";
}

}  // namespace

int main(int argc, char** argv) {
  rgbdi::system::SlamRunOptions opt;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* name) -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "rgbdi-slam: " << name << " needs a value\n";
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--input" || a == "-i")
      opt.input = value("--input");
    else if (a == "--out" || a == "-o")
      opt.out_dir = value("--out");
    else if (a == "--config")
      opt.config_path = value("--config");
    else if (a == "--gt")
      opt.gt_path = value("--gt");
    else if (a == "--no-depth")
      opt.no_depth = true;
    else if (a == "--no-loop")
      opt.no_loop = true;
    else if (a == "--save-simplemap")
      opt.save_simplemap = true;
    else if (a == "--sequential")
      opt.threaded = false;
    else if (a == "--quiet")
      opt.quiet = true;
    else if (a == "--help" || a == "-h") {
      usage(std::cout);
      return 0;
    } else {
      std::cerr << "rgbdi-slam: unknown argument '" << a << "'\n";
      usage(std::cerr);
      return 2;
    }
  }
  if (opt.input.empty() || opt.out_dir.empty()) {
    std::cerr << "rgbdi-slam: --input and --out are required\n";
    usage(std::cerr);
    return 2;
  }
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  opt.stop = &g_stop;
  try {
    const nlohmann::json summary = rgbdi::system::runSlam(opt, std::cerr);
    const auto& d = summary["stream_diagnostics"];
    if (d.value("refused", false)) return 1;  // nothing usable was delivered
    if (!summary["read_error"].is_null())
      return g_stop.load() ? 130 : 3;  // damaged, outputs written
  } catch (const rgbdi::system::UserError& e) {
    std::cerr << "rgbdi-slam: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-slam: error: " << e.what() << "\n";
    return 1;
  }
  return g_stop.load() ? 130 : 0;
}
