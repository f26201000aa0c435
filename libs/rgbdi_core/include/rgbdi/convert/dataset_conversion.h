// What `rawlog-convert INPUT -o OUT.rawlog` runs: detect the input format (ROS1 bag or TUM
// RGB-D folder), convert it into OUT.rawlog (+ OUT_groundtruth.tum, + OUT.ini with
// --camera-yaml), print progress and return the report. See doc/rawlog-convert.md.
#pragma once

#include <atomic>
#include <optional>
#include <ostream>
#include <string>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/conversion_report.h"
#include "rgbdi/bag/convert_options.h"
#include "rgbdi/convert/vins_yaml.h"

namespace rgbdi::convert {

/// Settings from the user's files: [convert] options and the calibration used where the input
/// has none ([camera] / [extrinsic] of --config, overridden by --camera-yaml).
struct ConversionSettings {
  bag::ConvertOptions options;
  bag::FallbackCalibration calibration = bag::FallbackCalibration::defaults();
  std::optional<VinsCalibration> vins;
};

/// Loads --config (an rgbdi INI; its other sections are allowed) and --camera-yaml (a VINS yaml);
/// either may be "". Throws ConfigError naming the file, section/key and the problem.
ConversionSettings loadConversionSettings(const std::string& config_path,
                                          const std::string& camera_yaml);

struct ConversionRequest {
  std::string input;   ///< bag file or TUM folder
  std::string output;  ///< *.rawlog or *.rawlog.gz
  ConversionSettings settings;
  bag::TopicOverrides topics;         ///< bags: topic names ("" = automatic, "none" = unused)
  std::optional<bool> depth_aligned;  ///< bags: override the layout's default
  std::string tum_camera;             ///< TUM: "" (auto), fr1, fr2, fr3, ros, config
  bool external_images = false;       ///< images in <stem>_Images/ instead of inside the rawlog
  std::ostream* progress = nullptr;   ///< progress line (nullptr: none)
  bool progress_interactive = false;  ///< redraw the progress line in place
  const std::atomic<bool>* stop = nullptr;  ///< set to stop early (the output stays valid)
};

/// Thrown for problems found before anything is written that are the user's to fix (wrong
/// output name, rawlog given as input, unknown TUM camera).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Converts. Problems found before writing throw: UsageError, ConfigError, IoError (unreadable
/// input, unknown format), bag::BagError (unreadable bag, missing topics listing the existing
/// ones, unusable calibration). Damage found while converting does not throw: the output is
/// finished with everything before it and report.error says what and where.
bag::ConversionReport convertDataset(const ConversionRequest& request);

}  // namespace rgbdi::convert
