// rawlog-convert: convert ROS1 bags (VINS-RGBD dataset, RealSense SDK recordings, other topics)
// and TUM RGB-D folders into MRPT rawlogs, and inspect datasets (--info).
// Only argument parsing and dispatch live here: the work is in the io, bag and convert stages.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/command_line.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/convert/input_description.h"
#include "rgbdi/io/input_format.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/stream_options.h"

namespace {

constexpr int kOk = rgbdi::kExitOk, kDataError = rgbdi::kExitError, kUsageError = rgbdi::kExitUsage,
              kDamaged = rgbdi::kExitDamaged, kInterrupted = rgbdi::kExitInterrupted;

const char* const kUsage =
    "Usage: rawlog-convert INPUT -o OUT.rawlog [options]   convert a ROS1 bag or a TUM RGB-D "
    "folder\n"
    "       rawlog-convert --info FILE [--json] [--config FILE] [--verbose]\n"
    "       rawlog-convert --help\n"
    "\n"
    "Inputs (detected by content): ROS1 bags (uncompressed, bz2 or lz4 chunks) in the VINS-RGBD\n"
    "dataset layout (/camera/color/image_raw, /camera/aligned_depth_to_color/image_raw, "
    "/camera/imu,\n"
    "/vrpn_client_node/<name>/pose), RealSense SDK recordings (/device_0/sensor_N/..., detected\n"
    "automatically) or any topics named below; TUM RGB-D folders (rgb.txt, depth.txt,\n"
    "accelerometer.txt, groundtruth.txt). Output: OUT.rawlog (CObservation3DRangeScan +\n"
    "CObservationIMU [+ CObservationOdometry]), OUT_groundtruth.tum when the input has ground\n"
    "truth, OUT.ini with --camera-yaml or a wheel extrinsic from the bag's /tf_static.\n"
    "\n"
    "Conversion options:\n"
    "  -o, --out FILE        output rawlog (*.rawlog; *.rawlog.gz is gzip-compressed)\n"
    "  -i, --input INPUT     the input (same as the positional INPUT)\n"
    "  --config FILE         rgbdi configuration: [camera] intrinsics and [extrinsic] used when "
    "the\n"
    "                        input has none, [convert] settings (default: share/config.ini "
    "values)\n"
    "  --camera-yaml FILE    VINS-RGBD calibration yaml (intrinsics, extrinsic, IMU noise, g, "
    "td);\n"
    "                        overrides --config's calibration and also writes OUT.ini for "
    "rgbdi-slam\n"
    "  --external-images     images as files in OUT_Images/ (colour PNG, depth range files) "
    "instead\n"
    "                        of inside the rawlog: keeps the rawlog small for large datasets\n"
    "  --require-colour      drop depth images without a colour partner (default: depth-only\n"
    "                        observations)\n"
    "  --pair-tolerance S    colour/depth stamps at most S seconds apart form a frame (default "
    "0.02)\n"
    "  --depth-unit M        metres per unit of 16-bit depth when the bag does not say (default "
    "0.001)\n"
    "  --depth-aligned yes|no  depth registered to the colour image (default: dataset yes,\n"
    "                        RealSense recordings no)\n"
    "  --color-topic T  --depth-topic T  --imu-topic T  --accel-topic T  --gyro-topic T\n"
    "  --groundtruth-topic T  --color-info-topic T  --depth-info-topic T\n"
    "                        topic names for bags in other layouts; 'none' disables a stream\n"
    "                        (--accel-topic with --gyro-topic: merged on the gyro stamps)\n"
    "  --odom-topic T        wheel odometry (nav_msgs/Odometry -> CObservationOdometry); default:\n"
    "                        the bag's only topic of that type; 'none' leaves it out. A\n"
    "                        /tf_static transform from the IMU's frame to the odometry's\n"
    "                        child frame is written to OUT.ini [wheel]\n"
    "  --tum-camera NAME     TUM intrinsics: fr1, fr2, fr3, ros or config (default: from the "
    "folder\n"
    "                        name)\n"
    "  --quiet               no progress line on stderr\n"
    "\n"
    "Inspection:\n"
    "  --info FILE           Inspect a dataset without converting. MRPT rawlogs (*.rawlog,\n"
    "                        *.rawlog.gz; external images in <name>_Images/): record counts, "
    "rates,\n"
    "                        gaps, ordering problems and data checks (IMU units, depth units, "
    "image\n"
    "                        sizes, intrinsics, sensorPose vs [extrinsic]). ROS1 bags: topics, "
    "types,\n"
    "                        counts, rates, the layout and calibration a conversion would use. "
    "TUM\n"
    "                        folders: the lists and the camera.\n"
    "  --json            With --info: print the result as one JSON object.\n"
    "  --verbose         With --info on rawlogs: also log every warning on stderr as it is found.\n"
    "  --version         Print the version.\n"
    "  -h, --help        Show this help.\n"
    "Options take their value as '--opt VALUE' or '--opt=VALUE'.\n"
    "\n"
    "Exit status: 0 success (warnings included); 1 unreadable or unusable input, output not\n"
    "written; 2 usage or configuration error; 3 damaged input (truncated, corrupt record or "
    "chunk,\n"
    "time going backwards): converted or inspected up to the damage, the output rawlog holds\n"
    "everything before it; 130 interrupted (Ctrl-C; the output holds what was converted).\n";

struct Args {
  std::optional<std::string> info;
  std::string input, output, config, camera_yaml, tum_camera;
  bool json = false, verbose = false, quiet = false, external_images = false;
  bool require_colour = false;
  std::optional<double> pair_tolerance, depth_unit;
  std::optional<bool> depth_aligned;
  rgbdi::bag::TopicOverrides topics;
};

double number(const std::string& option, const std::string& text) {
  const double v = rgbdi::parseNumber(option, text);
  if (v > 1e9) throw rgbdi::UsageError(option + " needs a non-negative number, got '" + text + "'");
  return v;
}

/// Throws rgbdi::UsageError with a message for the user.
rgbdi::CommandLine::Outcome parse(int argc, char** argv, Args& a) {
  rgbdi::CommandLine cl;
  std::string input_option;
  cl.value("--info", [&](const std::string& v) { a.info = v; });
  cl.value("--config", &a.config);
  cl.flag("--json", &a.json);
  cl.flag("--verbose", &a.verbose);
  cl.value("-o,--out", &a.output);
  cl.value("-i,--input", &input_option);
  cl.value("--camera-yaml", &a.camera_yaml);
  cl.flag("--external-images", &a.external_images);
  cl.flag("--require-colour,--require-color", &a.require_colour);
  cl.value("--pair-tolerance",
           [&](const std::string& v) { a.pair_tolerance = number("--pair-tolerance", v); });
  cl.value("--depth-unit", [&](const std::string& v) {
    a.depth_unit = number("--depth-unit", v);
    if (!(*a.depth_unit > 0.0) || *a.depth_unit > 1.0)
      throw rgbdi::UsageError("--depth-unit must be in (0, 1] metres per unit");
  });
  cl.value("--depth-aligned", [&](const std::string& v) {
    if (v != "yes" && v != "no")
      throw rgbdi::UsageError("--depth-aligned takes yes or no, got '" + v + "'");
    a.depth_aligned = v == "yes";
  });
  cl.value("--color-topic,--colour-topic", &a.topics.color);
  cl.value("--depth-topic", &a.topics.depth);
  cl.value("--imu-topic", &a.topics.imu);
  cl.value("--accel-topic", &a.topics.accel);
  cl.value("--gyro-topic", &a.topics.gyro);
  cl.value("--groundtruth-topic", &a.topics.groundtruth);
  cl.value("--color-info-topic,--colour-info-topic", &a.topics.color_info);
  cl.value("--depth-info-topic", &a.topics.depth_info);
  cl.value("--odom-topic", &a.topics.odometry);
  cl.value("--tum-camera", &a.tum_camera);
  cl.flag("--quiet", &a.quiet);
  const auto outcome = cl.parse(argc, argv);
  if (outcome != rgbdi::CommandLine::Outcome::Run) return outcome;
  // -i INPUT and a positional INPUT are the same thing.
  std::vector<std::string> positional = cl.positional();
  if (!input_option.empty()) positional.insert(positional.begin(), input_option);
  if (positional.size() > 1)
    throw rgbdi::UsageError("more than one input given ('" + positional[1] + "')");
  if (!positional.empty()) a.input = positional.front();
  return outcome;
}

int infoRawlog(const Args& a, const std::string& path) {
  rgbdi::io::StreamConfig cfg;
  if (!a.config.empty()) {
    try {
      rgbdi::IniReader ini = rgbdi::IniReader::fromFile(a.config);
      cfg = rgbdi::io::StreamConfig::load(ini);
    } catch (const rgbdi::ConfigError& e) {
      std::cerr << "rawlog-convert: " << e.what() << "\n";
      return kUsageError;
    }
  }
  rgbdi::io::StreamDiagnostics d;
  try {
    d = rgbdi::io::inspectRawlog(path, cfg, !a.verbose);
  } catch (const rgbdi::io::RawlogError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  std::cout << (a.json ? d.toJson() + "\n" : d.report());
  if (!d.ok()) {
    std::cerr << "rawlog-convert: " << d.error << "\n";
    return kDamaged;
  }
  return kOk;
}

int runInfo(const Args& a) {
  const std::string& path = *a.info;
  rgbdi::io::InputFormat format;
  try {
    format = rgbdi::io::detectInputFormat(path);
  } catch (const rgbdi::IoError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  if (format == rgbdi::io::InputFormat::Unknown) {
    std::cerr
        << "rawlog-convert: " << path
        << ": unrecognised format (expected an MRPT rawlog, a ROS1 bag or a TUM RGB-D folder)\n";
    return kDataError;
  }
  if (format == rgbdi::io::InputFormat::Rawlog) return infoRawlog(a, path);
  rgbdi::convert::ConversionSettings settings;
  rgbdi::io::StreamConfig stream;
  try {
    settings = rgbdi::convert::loadConversionSettings(a.config, a.camera_yaml);
    if (!a.config.empty()) {
      rgbdi::IniReader ini = rgbdi::IniReader::fromFile(a.config);
      stream = rgbdi::io::StreamConfig::load(ini);
    }
  } catch (const rgbdi::ConfigError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kUsageError;
  }
  rgbdi::convert::InputDescription d;
  try {
    d = format == rgbdi::io::InputFormat::Ros1Bag
            ? rgbdi::convert::describeBag(path, settings, a.topics, stream)
            : rgbdi::convert::describeTumFolder(path);
  } catch (const std::exception& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  std::cout << (a.json ? d.json + "\n" : d.text);
  if (!d.error.empty()) {
    std::cerr << "rawlog-convert: " << d.error << "\n";
    return kDamaged;
  }
  return kOk;
}

// Set from the SIGINT handler; a lock-free atomic is the one thing a handler may touch.
std::atomic<bool> g_stop{false};
extern "C" void onSigint(int) { g_stop.store(true); }

int runConversion(const Args& a) {
  rgbdi::convert::ConversionRequest q;
  q.input = a.input;
  q.output = a.output;
  try {
    q.settings = rgbdi::convert::loadConversionSettings(a.config, a.camera_yaml);
  } catch (const rgbdi::ConfigError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kUsageError;
  }
  if (a.pair_tolerance) q.settings.options.pair_tolerance_s = *a.pair_tolerance;
  if (q.settings.options.max_wait_s < q.settings.options.pair_tolerance_s)
    q.settings.options.max_wait_s = q.settings.options.pair_tolerance_s;
  if (a.depth_unit) q.settings.options.integer_depth_unit_m = *a.depth_unit;
  if (a.require_colour) q.settings.options.require_colour = true;
  q.topics = a.topics;
  q.depth_aligned = a.depth_aligned;
  q.tum_camera = a.tum_camera;
  q.external_images = a.external_images;
  q.progress = a.quiet ? nullptr : &std::cerr;
  q.progress_interactive = ::isatty(STDERR_FILENO) != 0;
  q.stop = &g_stop;
  std::signal(SIGINT, onSigint);

  rgbdi::bag::ConversionReport report;
  try {
    report = rgbdi::convert::convertDataset(q);
  } catch (const rgbdi::convert::UsageError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kUsageError;
  } catch (const rgbdi::ConfigError& e) {
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kUsageError;
  } catch (const std::exception& e) {
    // Unreadable input, missing topics, unusable calibration, output that cannot be written.
    std::cerr << "rawlog-convert: " << e.what() << "\n";
    return kDataError;
  }
  std::cout << report.text();
  if (!report.ok()) {
    std::cerr << "rawlog-convert: " << report.error << "\n";
    return kDamaged;
  }
  return g_stop.load() ? kInterrupted : kOk;
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  rgbdi::CommandLine::Outcome outcome;
  try {
    outcome = parse(argc, argv, a);
  } catch (const rgbdi::UsageError& e) {
    std::cerr << rgbdi::usageErrorLine("rawlog-convert", e.what());
    return kUsageError;
  }
  if (outcome == rgbdi::CommandLine::Outcome::Help) {
    std::cout << kUsage;
    return kOk;
  }
  if (outcome == rgbdi::CommandLine::Outcome::Version) {
    std::cout << rgbdi::versionLine("rawlog-convert") << "\n";
    return kOk;
  }
  if (a.info) {
    if (!a.input.empty() || !a.output.empty()) {
      std::cerr << "rawlog-convert: --info takes one input and writes nothing (drop INPUT / -o)\n";
      return kUsageError;
    }
    return runInfo(a);
  }
  if (a.input.empty() && a.output.empty()) {
    std::cerr << "rawlog-convert: nothing to do\n\n" << kUsage;
    return kUsageError;
  }
  if (a.input.empty()) {
    std::cerr << "rawlog-convert: no input given (rawlog-convert INPUT -o OUT.rawlog)\n";
    return kUsageError;
  }
  if (a.output.empty()) {
    std::cerr << "rawlog-convert: no output given (-o OUT.rawlog)\n";
    return kUsageError;
  }
  return runConversion(a);
}
