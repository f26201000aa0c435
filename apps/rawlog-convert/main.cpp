// rawlog-convert: inspect (and, in a later version, convert) sensor datasets.
// Only argument parsing and dispatch live here; each input format has its library function
// in the io stage (see rgbdi/io/input_format.h).
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/io/input_format.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/stream_options.h"

namespace {

constexpr int kOk = 0, kDataError = 1, kUsageError = 2;

const char* const kUsage =
    "Usage: rawlog-convert --info FILE [--json] [--config FILE] [--verbose]\n"
    "       rawlog-convert --help\n"
    "\n"
    "Options:\n"
    "  --info FILE     Inspect a dataset: record counts, rates, durations, gaps, ordering\n"
    "                  problems and data checks (IMU units, depth units, image sizes,\n"
    "                  intrinsics, sensorPose vs [extrinsic]). Supported: MRPT rawlogs\n"
    "                  (*.rawlog, *.rawlog.gz; external images in <name>_Images/).\n"
    "  --json          With --info: print the diagnostics as one JSON object.\n"
    "  --config FILE   rgbdi configuration; its [stream], [imu] and [extrinsic] sections set\n"
    "                  the thresholds (default: built-in values = share/config.ini).\n"
    "  --verbose       Also log every warning on stderr as it is found.\n"
    "  -h, --help      Show this help.\n"
    "\n"
    "Conversions (ROS1 bag / TUM RGB-D -> rawlog) are not supported yet.\n"
    "\n"
    "Exit status: 0 success (warnings included), 1 unreadable or corrupt data, 2 usage error.\n";

struct Args {
  std::optional<std::string> info;
  std::optional<std::string> config;
  bool json = false;
  bool verbose = false;
  bool help = false;
  std::vector<std::string> other;  ///< anything that would request a conversion
};

/// Throws std::invalid_argument with a message for the user.
Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* opt) {
      if (i + 1 >= argc) throw std::invalid_argument(std::string(opt) + " needs a value");
      return std::string(argv[++i]);
    };
    if (arg == "-h" || arg == "--help") {
      a.help = true;
    } else if (arg == "--info") {
      a.info = value("--info");
    } else if (arg == "--config") {
      a.config = value("--config");
    } else if (arg == "--json") {
      a.json = true;
    } else if (arg == "--verbose") {
      a.verbose = true;
    } else if (!arg.empty() && arg[0] == '-' && arg != "-i" && arg != "-o") {
      throw std::invalid_argument("unknown option '" + arg + "'");
    } else {
      a.other.push_back(arg);
    }
  }
  return a;
}

using Inspector = std::function<rgbdi::io::StreamDiagnostics(const std::string&,
                                                             const rgbdi::io::StreamConfig&, bool)>;

/// Input formats `--info` can read; a format plugs in here with its library function.
const std::map<rgbdi::io::InputFormat, Inspector>& inspectors() {
  static const std::map<rgbdi::io::InputFormat, Inspector> table = {
      {rgbdi::io::InputFormat::Rawlog, &rgbdi::io::inspectRawlog},
  };
  return table;
}

int runInfo(const Args& a) {
  rgbdi::io::StreamConfig cfg;
  if (a.config) {
    try {
      rgbdi::IniReader ini = rgbdi::IniReader::fromFile(*a.config);
      cfg = rgbdi::io::StreamConfig::load(ini);
    } catch (const rgbdi::ConfigError& e) {
      std::cerr << "rawlog-convert: " << e.what() << "\n";
      return kUsageError;
    }
  }
  const std::string& path = *a.info;
  rgbdi::io::InputFormat format;
  try {
    format = rgbdi::io::detectInputFormat(path);
  } catch (const rgbdi::IoError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  const auto it = inspectors().find(format);
  if (format == rgbdi::io::InputFormat::Unknown) {
    std::cerr << "rawlog-convert: " << path
              << ": unrecognised format (expected an MRPT rawlog: *.rawlog or *.rawlog.gz)\n";
    return kDataError;
  }
  if (it == inspectors().end()) {
    std::cerr << "rawlog-convert: " << path << ": --info on a " << rgbdi::io::formatName(format)
              << " is not yet supported (only MRPT rawlogs for now)\n";
    return kUsageError;
  }
  rgbdi::io::StreamDiagnostics d;
  try {
    d = it->second(path, cfg, !a.verbose);
  } catch (const rgbdi::io::RawlogError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  if (a.json) {
    std::cout << d.toJson() << "\n";
  } else {
    std::cout << d.report();
  }
  if (!d.ok()) {
    std::cerr << "rawlog-convert: " << d.error << "\n";
    return kDataError;
  }
  return kOk;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  try {
    a = parse(argc, argv);
  } catch (const std::invalid_argument& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n\n" << kUsage;
    return kUsageError;
  }
  if (a.help) {
    std::cout << kUsage;
    return kOk;
  }
  if (!a.other.empty()) {
    std::cerr << "rawlog-convert: converting datasets (" << a.other.front()
              << " ...) is not yet supported; only --info is available in this version\n";
    return kUsageError;
  }
  if (!a.info) {
    std::cerr << "rawlog-convert: nothing to do\n\n" << kUsage;
    return kUsageError;
  }
  return runInfo(a);
}
