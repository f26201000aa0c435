// rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt S] [--rpe-delta S] [--json]
//            [--navmap EST_LAYERS --navmap-truth TRUE_LAYERS [--navmap-sloped-deg DEG]
//            [--navmap-diff PNG]]
// Trajectory accuracy (ATE, RPE, coverage) of an estimate against ground truth; the method is in
// doc/evaluation.md. With --navmap, also the navigation map against the simulator's true one in
// the frame of the trajectory alignment (doc/navigation-maps.md). Exit codes: 0 ok, 1 bad data
// (files, no overlap), 2 bad usage. Options are parsed by rgbdi::CommandLine (the tools' shared
// parser).
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/command_line.h"
#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/navmap/navmap_compare.h"
#include "rgbdi/navmap/navmap_files.h"

namespace {

const char* const kUsage =
    "usage: rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt SECONDS]\n"
    "                  [--rpe-delta SECONDS] [--json]\n"
    "  GT.tum, EST.tum  TUM trajectories: 't tx ty tz qx qy qz qw' per line ('#' comments)\n"
    "  --align          alignment of the estimate onto the ground truth (default se3)\n"
    "  --max-dt         timestamp association tolerance [s] (default 0.02)\n"
    "  --rpe-delta      relative pose error step [s] (default 1)\n"
    "  --json           print exactly one JSON object instead of the text report\n"
    "  --navmap         navmap_layers.yml.gz of the run whose trajectory EST.tum is: compared\n"
    "                   with --navmap-truth (a simulator's truth_navmap_layers.yml.gz) in the "
    "frame\n"
    "                   of the trajectory alignment (use --align posyaw)\n"
    "  --navmap-sloped-deg  true slope from which free ground counts as a ramp (default 2)\n"
    "  --navmap-diff    PNG of the comparison: agreeing cells white (free) and black (occupied),\n"
    "                   true free estimated occupied red, true occupied estimated free blue\n"
    "                   (lighter where within one cell of a true boundary: tolerated)\n"
    "  --version        print the version\n"
    "  -h, --help       this help\n"
    "Options take their value as '--opt VALUE' or '--opt=VALUE'. Status 3 is not used by this "
    "tool.\n";

struct Arguments {
  std::string gt_path;
  std::string est_path;
  rgbdi::eval::EvalOptions options;
  bool json = false;
  std::string navmap, navmap_truth, navmap_diff;
  double sloped_deg = 2.0;
};

double positiveSeconds(const std::string& option, const std::string& text) {
  try {
    return rgbdi::parseNumber(option, text, true);
  } catch (const rgbdi::UsageError&) {
    throw rgbdi::UsageError(option + " needs a positive number of seconds, got '" + text + "'");
  }
}

/// Throws rgbdi::UsageError.
rgbdi::CommandLine::Outcome parse(int argc, char** argv, Arguments& a) {
  rgbdi::CommandLine cl;
  cl.flag("--json", &a.json);
  cl.value("--navmap", &a.navmap);
  cl.value("--navmap-truth", &a.navmap_truth);
  cl.value("--navmap-diff", &a.navmap_diff);
  cl.value("--navmap-sloped-deg", [&](const std::string& v) {
    a.sloped_deg = rgbdi::parseNumber("--navmap-sloped-deg", v, true);
  });
  cl.value("--align", [&](const std::string& v) {
    try {
      a.options.align = rgbdi::eval::parseAlignMode(v);
    } catch (const std::invalid_argument& e) {
      throw rgbdi::UsageError(std::string("--align: ") + e.what());
    }
  });
  cl.value("--max-dt",
           [&](const std::string& v) { a.options.max_dt_s = positiveSeconds("--max-dt", v); });
  cl.value("--rpe-delta", [&](const std::string& v) {
    a.options.rpe.delta_s = positiveSeconds("--rpe-delta", v);
  });
  const auto outcome = cl.parse(argc, argv);
  if (outcome != rgbdi::CommandLine::Outcome::Run) return outcome;
  const auto& positional = cl.positional();
  if (positional.size() != 2) {
    throw rgbdi::UsageError("expected 2 trajectory files (GT.tum EST.tum), got " +
                            std::to_string(positional.size()));
  }
  if (!a.navmap_diff.empty() && a.navmap.empty())
    throw rgbdi::UsageError("--navmap-diff needs --navmap and --navmap-truth");
  if (a.navmap.empty() != a.navmap_truth.empty())
    throw rgbdi::UsageError("--navmap and --navmap-truth go together");
  a.gt_path = positional[0];
  a.est_path = positional[1];
  return outcome;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  rgbdi::CommandLine::Outcome outcome;
  try {
    outcome = parse(argc, argv, args);
  } catch (const rgbdi::UsageError& e) {
    std::cerr << rgbdi::usageErrorLine("rgbdi-eval", e.what());
    return rgbdi::kExitUsage;
  }
  if (outcome == rgbdi::CommandLine::Outcome::Help) {
    std::cout << kUsage << "\n" << rgbdi::exitStatusHelp();
    return rgbdi::kExitOk;
  }
  if (outcome == rgbdi::CommandLine::Outcome::Version) {
    std::cout << rgbdi::versionLine("rgbdi-eval") << "\n";
    return rgbdi::kExitOk;
  }
  try {
    const rgbdi::Trajectory gt = rgbdi::eval::readTum(args.gt_path);
    const rgbdi::Trajectory est = rgbdi::eval::readTum(args.est_path);
    rgbdi::eval::EvalResult result;
    try {
      result = rgbdi::eval::evaluate(gt, est, args.options);
    } catch (const rgbdi::eval::EvalError& e) {
      throw rgbdi::eval::EvalError(args.est_path + " vs " + args.gt_path + ": " + e.what());
    }
    nlohmann::json json = rgbdi::eval::toJson(result);
    std::string report = rgbdi::eval::formatReport(result);
    if (!args.navmap.empty()) {
      const rgbdi::navmap::NavMap est_map = rgbdi::navmap::readLayers(args.navmap);
      const rgbdi::navmap::NavMap true_map = rgbdi::navmap::readLayers(args.navmap_truth);
      // p_gt = scale * R * p_est + t; the maps are compared rigidly (scale 1 for posyaw/se3).
      const rgbdi::navmap::NavMapComparison c = rgbdi::navmap::compareNavMaps(
          est_map, true_map, result.alignment.rigid().inverse(), args.sloped_deg);
      json["navmap"] = c.toJson();
      if (!args.navmap_diff.empty())
        rgbdi::navmap::writeComparisonPicture(est_map, true_map, result.alignment.rigid().inverse(),
                                              args.navmap_diff);
      std::ostringstream os;
      os << std::fixed << std::setprecision(1) << "navmap: observed " << c.observed << " of "
         << c.true_known << " known true cells; free " << 100 * c.freeRecall() << " % ("
         << 100 * c.freeRecallTolerant() << " % within one cell), occupied "
         << 100 * c.occupiedRecall() << " % (" << 100 * c.occupiedRecallTolerant()
         << " %), driven free " << 100 * c.drivenFree() << " %, ramps free " << 100 * c.slopedFree()
         << " %, edges/holes occupied " << 100 * c.edgesOccupied() << " % ("
         << 100 * c.edgesOccupiedTolerant() << " %); ground height RMSE " << std::setprecision(3)
         << c.height_rmse_m << " m (bias " << c.height_bias_m << " m) over " << c.height_cells
         << " cells\n";
      report += os.str();
    }
    if (args.json) {
      std::cout << json.dump() << "\n";
    } else {
      std::cout << report;
    }
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-eval: " << e.what() << "\n";
    return rgbdi::kExitError;
  }
  return 0;
}
