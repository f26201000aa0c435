// rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt S] [--rpe-delta S] [--json]
// Trajectory accuracy (ATE, RPE, coverage) of an estimate against ground truth; the method is in
// doc/evaluation.md. Exit codes: 0 ok, 1 bad data (files, no overlap), 2 bad usage.
// Options are parsed by rgbdi::CommandLine (the tools' shared parser).
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/command_line.h"
#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"

namespace {

const char* const kUsage =
    "usage: rgbdi-eval GT.tum EST.tum [--align se3|sim3|posyaw|none] [--max-dt SECONDS]\n"
    "                  [--rpe-delta SECONDS] [--json]\n"
    "  GT.tum, EST.tum  TUM trajectories: 't tx ty tz qx qy qz qw' per line ('#' comments)\n"
    "  --align          alignment of the estimate onto the ground truth (default se3)\n"
    "  --max-dt         timestamp association tolerance [s] (default 0.02)\n"
    "  --rpe-delta      relative pose error step [s] (default 1)\n"
    "  --json           print exactly one JSON object instead of the text report\n"
    "  --version        print the version\n"
    "  -h, --help       this help\n"
    "Options take their value as '--opt VALUE' or '--opt=VALUE'. Status 3 is not used by this "
    "tool.\n";

struct Arguments {
  std::string gt_path;
  std::string est_path;
  rgbdi::eval::EvalOptions options;
  bool json = false;
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
    if (args.json) {
      std::cout << rgbdi::eval::toJson(result).dump() << "\n";
    } else {
      std::cout << rgbdi::eval::formatReport(result);
    }
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-eval: " << e.what() << "\n";
    return rgbdi::kExitError;
  }
  return 0;
}
