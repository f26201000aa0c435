// rgbdi-sim --profile NAME --out DIR [--duration S] [--speed slow|normal|fast] [--fps N]
//           [--seed N] [--variant N] [--config FILE] [--time-offset S] [--aliased-walls]
//           [--bag [--bag-compression none|bz2|lz4]]
// rgbdi-sim --profile recorded --recording DIR [--recording-format euroc] --out DIR [...]
// Simulates an RGB-D-inertial sequence (doc/simulator.md) and writes it to DIR. Exit codes:
// 0 ok, 1 error (files, a sequence that cannot be made), 2 bad usage or configuration,
// 130 interrupted (Ctrl-C). Options are parsed by rgbdi::CommandLine.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/command_line.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/navmap/navmap_files.h"
#include "rgbdi/sim/recording.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/sim/world_truth.h"

namespace {

using rgbdi::kExitError;
using rgbdi::kExitInterrupted;
using rgbdi::kExitUsage;

const char* const kUsage =
    "usage: rgbdi-sim --profile NAME --out DIR [--duration S] [--speed slow|normal|fast]\n"
    "                 [--fps N] [--seed N] [--variant N] [--config FILE] [--time-offset S]\n"
    "                 [--aliased-walls] [--blackout START:DURATION[:KIND]]\n"
    "                 [--spin START:DURATION[:TURNS]]\n"
    "                 [--bag [--bag-compression none|bz2|lz4]] [--embedded-images]\n"
    "       rgbdi-sim --profile recorded --recording DIR [--recording-format euroc] --out DIR\n"
    "                 [--duration S] [--fps N] [--seed N] [--config FILE] [...]\n"
    "  --profile          handheld | wheeled_circle | wheeled_slopes | tracked_slopes |\n"
    "                     recorded (a hybrid sequence: the real IMU and ground truth of\n"
    "                     --recording, images rendered along the ground truth)\n"
    "  --recording        directory of a real recording (IMU + ground truth; --profile recorded)\n"
    "  --recording-format its format: euroc (default; imu0.csv + groundtruth.csv or the ASL\n"
    "                     mav0/ layout)\n"
    "  --out              output directory (sequence.rawlog, sequence_Images/, groundtruth.tum,\n"
    "                     groundtruth_cam.tum, config.ini, simulation.ini[, sequence.bag,\n"
    "                     vins_config.yaml], truth_navmap.*: the true navigation maps of the\n"
    "                     path, [navmap] limits)\n"
    "  --duration         total duration [s] (default: the profile's; recorded: the recording\n"
    "                     from its first ground-truth sample inside the IMU's span)\n"
    "  --speed            speed preset (wheeled_slopes: the paper's slow/normal/fast runs)\n"
    "  --fps              camera frame rate [Hz] (default 30)\n"
    "  --seed             random seed of noise and textures (default 1)\n"
    "  --variant          path in the same world: 0 = the profile's path (default), 1 = the\n"
    "                     same closed path from another start driven the other way round,\n"
    "                     2 = from a third start, same direction; ground truth in the\n"
    "                     world frame of every variant\n"
    "  --config           INI file with [sim], [camera], [extrinsic] (default: built-in values,\n"
    "                     the same as share/config.ini); world variation in [sim]: world_seed\n"
    "                     (other furniture), room_margin_m, furniture_density,\n"
    "                     furniture_lateral_max_m, texture_contrast, exposure_gain_amplitude,\n"
    "                     exposure_period_s (auto-exposure drift); D435i realism (default\n"
    "                     off): imu_* errors and imu_accel_rate_hz / imu_gyro_rate_hz streams,\n"
    "                     depth_* artefacts, frame_stamp_jitter_s; doc/simulator.md\n"
    "  --time-offset      camera-IMU time offset [s]: images stamped t_imu - offset\n"
    "  --aliased-walls    the room's +x wall repeats the -x wall (perceptual aliasing)\n"
    "  --blackout         frames from START for DURATION seconds (sequence time, e.g. 20:3)\n"
    "                     are impaired (IMU unaffected): KIND black (default: black with no\n"
    "                     depth, a covered lens), bare (no texture: a bare wall; depth kept)\n"
    "                     or blur (motion blur; depth kept), e.g. 20:2:blur\n"
    "  --spin             extreme rotation: from START for DURATION seconds the body turns\n"
    "                     TURNS times (default 1; negative: clockwise) about the vertical on\n"
    "                     top of its motion; peak rate 13.7 * TURNS / DURATION rad/s, e.g.\n"
    "                     20:1.5 (9.2 rad/s)\n"
    "  --bag              also write sequence.bag (ROS1, the published dataset's layout; with\n"
    "                     wheel encoders also /odom nav_msgs/Odometry and /tf_static)\n"
    "  --bag-compression  chunk compression of the bag (default none)\n"
    "  --embedded-images  raw images inside sequence.rawlog (as a live camera delivers them:\n"
    "                     nothing to decode, 1.5 MB per 640x480 frame) instead of PNG and\n"
    "                     compressed range files in sequence_Images/\n"
    "  --version          print the version\n"
    "  -h, --help         this help\n"
    "Options take their value as '--opt VALUE' or '--opt=VALUE'. Status 3 is not used by this "
    "tool.\nInterrupted (130), it writes no rawlog and no bag: a sequence is complete or absent.\n";

using rgbdi::UsageError;

// Set from the SIGINT handler; a lock-free atomic is the one thing a handler may touch.
std::atomic<bool> g_stop{false};
extern "C" void onSigint(int) { g_stop.store(true); }

double number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw UsageError(option + " needs a number, got '" + text + "'");
  return v;
}

/// START:DURATION[:EXTRA] of --blackout and --spin (seconds of sequence time).
struct Span {
  double start = 0.0, duration = 0.0;
  std::string extra;  ///< empty when not given
};

Span parseSpan(const std::string& option, const std::string& extra_name, const std::string& v) {
  const auto colon = v.find(':');
  if (colon == std::string::npos)
    throw UsageError(option + " needs START:DURATION[:" + extra_name + "] in seconds, got '" + v +
                     "'");
  Span span;
  span.start = number(option + " start", v.substr(0, colon));
  std::string rest = v.substr(colon + 1);
  const auto colon2 = rest.find(':');
  if (colon2 != std::string::npos) {
    span.extra = rest.substr(colon2 + 1);
    rest = rest.substr(0, colon2);
  }
  span.duration = number(option + " duration", rest);
  if (span.start < 0.0 || span.duration <= 0.0)
    throw UsageError(option + ": START must be >= 0 and DURATION > 0, got '" + v + "'");
  return span;
}

struct Arguments {
  std::string profile, out, config, speed, bag_compression = "none";
  std::string recording, recording_format = "euroc";
  double duration = 0.0, fps = 0.0, time_offset = 0.0;
  double blackout_start = 0.0, blackout_duration = 0.0;
  double spin_start = 0.0, spin_duration = 0.0, spin_turns = 0.0;  ///< turns 0: the configuration's
  std::string blackout_kind;                                       ///< empty: the configuration's
  long long seed = -1;
  int variant = -1;
  bool has_time_offset = false, bag = false, aliased_walls = false, embedded_images = false;
};

/// Throws UsageError.
rgbdi::CommandLine::Outcome parse(int argc, char** argv, Arguments& a) {
  rgbdi::CommandLine cl;
  cl.value("--profile", &a.profile);
  cl.value("--out", &a.out);
  cl.value("--config", &a.config);
  cl.value("--speed", &a.speed);
  cl.value("--recording", &a.recording);
  cl.value("--recording-format", &a.recording_format);
  cl.value("--duration", [&](const std::string& v) {
    a.duration = number("--duration", v);
    if (a.duration <= 0.0) throw UsageError("--duration must be positive");
  });
  cl.value("--fps", [&](const std::string& v) {
    a.fps = number("--fps", v);
    if (a.fps <= 0.0 || a.fps > 1000.0) throw UsageError("--fps must be in (0, 1000]");
  });
  cl.value("--seed", [&](const std::string& v) {
    const double s = number("--seed", v);
    if (s < 0 || s > std::numeric_limits<int>::max() || s != std::floor(s))
      throw UsageError("--seed must be an integer in [0, 2147483647]");
    a.seed = static_cast<long long>(s);
  });
  cl.value("--variant", [&](const std::string& v) {
    const double n = number("--variant", v);
    if (n < 0 || n >= rgbdi::sim::kProfileVariants || n != std::floor(n))
      throw UsageError("--variant must be an integer in [0, " +
                       std::to_string(rgbdi::sim::kProfileVariants - 1) + "]");
    a.variant = static_cast<int>(n);
  });
  cl.value("--time-offset", [&](const std::string& v) {
    a.time_offset = number("--time-offset", v);
    if (std::abs(a.time_offset) > 0.5) throw UsageError("--time-offset must be within +-0.5 s");
    a.has_time_offset = true;
  });
  cl.flag("--aliased-walls", &a.aliased_walls);
  cl.value("--blackout", [&](const std::string& v) {
    const Span span = parseSpan("--blackout", "KIND", v);
    if (!span.extra.empty() && !rgbdi::sim::isBlackoutKind(span.extra))
      throw UsageError("--blackout: KIND must be black, bare or blur, got '" + span.extra + "'");
    a.blackout_start = span.start;
    a.blackout_duration = span.duration;
    a.blackout_kind = span.extra;
  });
  cl.value("--spin", [&](const std::string& v) {
    const Span span = parseSpan("--spin", "TURNS", v);
    if (!span.extra.empty()) {
      a.spin_turns = number("--spin turns", span.extra);
      if (a.spin_turns == 0.0 || std::abs(a.spin_turns) > 100.0)
        throw UsageError("--spin: TURNS must be non-zero and within +-100, got '" + v + "'");
    }
    a.spin_start = span.start;
    a.spin_duration = span.duration;
  });
  cl.flag("--bag", &a.bag);
  cl.flag("--embedded-images", &a.embedded_images);
  cl.value("--bag-compression", &a.bag_compression);
  const auto outcome = cl.parse(argc, argv);
  if (outcome != rgbdi::CommandLine::Outcome::Run) return outcome;
  if (!cl.positional().empty())
    throw UsageError("unexpected argument '" + cl.positional().front() + "'");
  if (a.profile.empty()) throw UsageError("--profile is required");
  if (a.out.empty()) throw UsageError("--out is required");
  if (a.profile == "recorded") {
    if (a.recording.empty()) throw UsageError("--profile recorded needs --recording DIR");
    const auto& formats = rgbdi::sim::recordingFormats();
    if (std::find(formats.begin(), formats.end(), a.recording_format) == formats.end())
      throw UsageError("--recording-format: unknown format '" + a.recording_format + "'");
    // The motion and the IMU are the recording's.
    if (!a.speed.empty() || a.variant >= 0 || a.spin_duration > 0.0)
      throw UsageError("--speed, --variant and --spin do not apply to --profile recorded");
  } else if (!a.recording.empty()) {
    throw UsageError("--recording needs --profile recorded");
  }
  return outcome;
}

rgbdi::sim::SimOptions options(const Arguments& a, rgbdi::navmap::NavMapOptions* navmap) {
  rgbdi::IniReader ini =
      a.config.empty() ? rgbdi::IniReader::empty() : rgbdi::IniReader::fromFile(a.config);
  rgbdi::sim::SimOptions o = rgbdi::sim::SimOptions::load(ini);
  // The robot's limits of the true navigation map.
  *navmap = rgbdi::navmap::NavMapOptions::load(ini);
  // The simulator reads [sim], [camera], [extrinsic] and [navmap]; the other modules' sections
  // of a full rgbdi configuration (e.g. share/config.ini) are allowed but not used.
  ini.acceptConfigSectionsExcept({"sim", "camera", "extrinsic", "navmap"});
  ini.checkNoUnknownKeys();
  if (a.profile == "recorded") {
    o.profile.kind = rgbdi::sim::ProfileKind::Recorded;
    const auto recording = std::make_shared<const rgbdi::sim::Recording>(
        rgbdi::sim::readRecording(a.recording, a.recording_format));
    o.recording = recording;
    // Without an [extrinsic] of its own, the camera sits where the dataset's camera was.
    if (!ini.hasKey("extrinsic", "R_body_cam") && !ini.hasKey("extrinsic", "t_body_cam_m"))
      o.extrinsic.T_body_cam = recording->T_body_cam;
  } else {
    try {
      o.profile.kind = rgbdi::sim::parseProfileKind(a.profile);
      if (!a.speed.empty()) o.profile.speed = rgbdi::sim::parseSpeedPreset(a.speed);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string(e.what()) + " or recorded");
    }
  }
  if (a.duration > 0.0) o.profile.duration_s = a.duration;
  if (a.fps > 0.0) o.fps = a.fps;
  if (a.seed >= 0) o.seed = static_cast<std::uint64_t>(a.seed);
  if (a.variant >= 0) o.profile.variant = a.variant;
  if (a.has_time_offset) o.time_offset_s = a.time_offset;
  if (a.aliased_walls) o.scene.aliased_walls = true;
  if (a.blackout_duration > 0.0) {
    o.blackout_start_s = a.blackout_start;
    o.blackout_duration_s = a.blackout_duration;
    if (!a.blackout_kind.empty()) o.blackout_kind = a.blackout_kind;
  }
  if (a.spin_duration > 0.0) {
    o.spin_start_s = a.spin_start;
    o.spin_duration_s = a.spin_duration;
    if (a.spin_turns != 0.0) o.spin_turns = a.spin_turns;
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  rgbdi::sim::SimOptions opt;
  rgbdi::navmap::NavMapOptions navmap_options;
  rgbdi::sim::SequenceWriterOptions wo;
  try {
    const auto outcome = parse(argc, argv, args);
    if (outcome == rgbdi::CommandLine::Outcome::Help) {
      std::cout << kUsage << rgbdi::exitStatusHelp();
      return 0;
    }
    if (outcome == rgbdi::CommandLine::Outcome::Version) {
      std::cout << rgbdi::versionLine("rgbdi-sim") << "\n";
      return 0;
    }
    try {
      wo.bag_compression = rgbdi::bag::parseCompression(args.bag_compression);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--bag-compression: ") + e.what());
    }
    opt = options(args, &navmap_options);
  } catch (const UsageError& e) {
    std::cerr << rgbdi::usageErrorLine("rgbdi-sim", e.what());
    return kExitUsage;
  } catch (const rgbdi::ConfigError& e) {
    std::cerr << "rgbdi-sim: " << e.what() << "\n";
    return kExitUsage;
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-sim: error: " << e.what() << "\n";
    return kExitError;
  }

  std::signal(SIGINT, onSigint);
  try {
    const rgbdi::sim::SimulatedSequence sequence(opt);
    wo.write_bag = args.bag;
    wo.external_images = !args.embedded_images;
    wo.progress = &std::cerr;
    wo.progress_interactive = ::isatty(STDERR_FILENO) != 0;
    const rgbdi::sim::SequenceWriteSummary s =
        rgbdi::sim::writeSequence(sequence, args.out, wo, &g_stop);
    if (!s.completed) {
      std::cerr << "rgbdi-sim: interrupted after " << s.frames << " of " << sequence.frameCount()
                << " frames; no rawlog or bag was written\n";
      return kExitInterrupted;
    }
    std::cout << std::fixed << std::setprecision(1) << "profile " << args.profile
              << (opt.profile.variant != 0 ? " variant " + std::to_string(opt.profile.variant)
                                           : std::string())
              << ": " << sequence.duration() << " s, " << sequence.profile().path_length_m
              << " m at " << std::setprecision(3) << sequence.profile().cruise_speed_m_s << " m/s, "
              << s.frames << " frames, " << s.imu_samples << " IMU samples in "
              << std::setprecision(1) << s.wall_time_s << " s ("
              << s.frames / std::max(1e-9, s.wall_time_s) << " frames/s)\n"
              << "  " << s.rawlog_path << "\n  " << s.groundtruth_path << "\n  "
              << s.groundtruth_cam_path << "\n  " << s.config_path << "\n  " << s.simulation_path
              << "\n";
    if (!s.bag_path.empty()) std::cout << "  " << s.bag_path << "\n";
    if (!s.vins_config_path.empty()) std::cout << "  " << s.vins_config_path << "\n";
    // The true navigation maps of the world along the true path (doc/navigation-maps.md).
    const std::vector<Eigen::Vector3d> path = rgbdi::sim::truePath(sequence);
    const rgbdi::navmap::NavMap truth = rgbdi::sim::trueNavMap(sequence, navmap_options);
    for (const auto& [name, file] :
         rgbdi::navmap::writeNavMapFiles(truth, args.out, &path, "truth_navmap"))
      if (name == "truth_navmap_layers" || name == "truth_navmap_yaml" ||
          name == "truth_navmap_png")
        std::cout << "  " << file << "\n";
  } catch (const std::exception& e) {
    std::cerr << "rgbdi-sim: error: " << e.what() << "\n";
    return kExitError;
  }
  return 0;
}
