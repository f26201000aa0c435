// rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt S] [--rpe-delta S] [--json]
// Trajectory accuracy (ATE, RPE, coverage) of an estimate against ground truth; the method is in
// doc/evaluation.md. Exit codes: 0 ok, 1 bad data (files, no overlap), 2 bad usage.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"

namespace {

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;

const char* const kUsage =
    "usage: rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt SECONDS]\n"
    "                  [--rpe-delta SECONDS] [--json]\n"
    "  GT.tum, EST.tum  TUM trajectories: 't tx ty tz qx qy qz qw' per line ('#' comments)\n"
    "  --align          alignment of the estimate onto the ground truth (default se3)\n"
    "  --max-dt         timestamp association tolerance [s] (default 0.02)\n"
    "  --rpe-delta      relative pose error step [s] (default 1)\n"
    "  --json           print exactly one JSON object instead of the text report\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Arguments {
  std::string gt_path;
  std::string est_path;
  rgbdi::eval::EvalOptions options;
  bool json = false;
  bool help = false;
};

double positiveSeconds(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v <= 0.0) {
    throw UsageError(option + " needs a positive number of seconds, got '" + text + "'");
  }
  return v;
}

Arguments parse(int argc, char** argv) {
  Arguments a;
  std::vector<std::string> positional;
  for (int k = 1; k < argc; ++k) {
    std::string arg = argv[k];
    std::string value;
    bool has_inline_value = false;
    if (arg.rfind("--", 0) == 0 && arg.find('=') != std::string::npos) {
      value = arg.substr(arg.find('=') + 1);
      arg = arg.substr(0, arg.find('='));
      has_inline_value = true;
    }
    const auto takeValue = [&]() -> std::string {
      if (has_inline_value) return value;
      if (k + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++k];
    };
    if (arg == "--help" || arg == "-h") {
      a.help = true;
    } else if (arg == "--json") {
      if (has_inline_value) throw UsageError("--json takes no value");
      a.json = true;
    } else if (arg == "--align") {
      try {
        a.options.align = rgbdi::eval::parseAlignMode(takeValue());
      } catch (const std::invalid_argument& e) {
        throw UsageError(std::string("--align: ") + e.what());
      }
    } else if (arg == "--max-dt") {
      a.options.max_dt_s = positiveSeconds(arg, takeValue());
    } else if (arg == "--rpe-delta") {
      a.options.rpe.delta_s = positiveSeconds(arg, takeValue());
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw UsageError("unknown option '" + arg + "'");
    } else {
      positional.push_back(arg);
    }
  }
  if (a.help) return a;
  if (positional.size() != 2) {
    throw UsageError("expected 2 trajectory files (GT.tum EST.tum), got " +
                     std::to_string(positional.size()));
  }
  a.gt_path = positional[0];
  a.est_path = positional[1];
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  try {
    args = parse(argc, argv);
  } catch (const UsageError& e) {
    std::cerr << "rgbdi-eval: " << e.what() << " (see rgbdi-eval --help)\n";
    return kExitUsage;
  }
  if (args.help) {
    std::cout << kUsage;
    return 0;
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
    if (args.json) {
      std::cout << rgbdi::eval::toJson(result).dump() << "\n";
    } else {
      std::cout << rgbdi::eval::formatReport(result);
    }
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-eval: " << e.what() << "\n";
    return kExitData;
  }
  return 0;
}
