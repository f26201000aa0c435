// What the offline and the live rgbdi-slam runs share: the checks before a run (configuration,
// ground truth, output directory) and everything after the stream has ended (stream problems on
// the console, evaluation, every output file, summary.json, the report). Both runners call these
// so that a live run writes exactly what an offline run writes.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <ostream>
#include <stdexcept>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/io/stream_diagnostics.h"
#include "rgbdi/map/map_data.h"
#include "rgbdi/system/slam_summary.h"
#include "rgbdi/system/slam_system.h"
#include "rgbdi/system/system_config.h"

namespace rgbdi::system {

/// A problem with the inputs that the user must fix (missing file, bad config, unwritable output).
class UserError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A configuration file (--config, the sensors file of --live) that cannot be used: a bad line,
/// key or value. The tools report it as a usage/configuration error (exit status 2).
class RunConfigError : public UserError {
 public:
  using UserError::UserError;
};

/// The run's configuration ("" = built-in defaults); ConfigError becomes RunConfigError.
SystemConfig loadRunConfig(const std::string& path);
/// Ground truth (TUM) or an empty trajectory for ""; throws UserError.
Trajectory readGroundTruth(const std::string& path);
/// Creates `dir` and checks that it is writable; throws UserError.
void prepareOutputDir(const std::string& dir);

/// The map options of a run (rgbdi-slam --load-map, --localize-only, --no-save-map).
struct MapRunOptions {
  std::string load_dir;        ///< saved map to start in ("" = a new map)
  bool localize_only = false;  ///< with load_dir: the map stays as loaded and is not saved again
  bool save = true;            ///< write DIR/map/ at the end (doc/maps.md)
};

/// Reads the saved map of `options.load_dir` (nullptr when none) and checks it against the
/// run's configuration (calibration, descriptor type, loop closure on); throws UserError naming
/// the file and what is wrong.
std::shared_ptr<const map::MapData> loadRunMap(const MapRunOptions& options,
                                               const SystemConfig& cfg);

struct RunOutputOptions {
  std::string out_dir;
  std::string gt_path;          ///< named in the report ("" = none)
  bool save_simplemap = false;  ///< also keyframes.simplemap (needs keep_observations)
  MapRunOptions map;            ///< DIR/map/ saved after every thread has stopped
};

/// After endOfStream: prints every stream problem once, evaluates against `gt` (skipped when
/// empty), writes every output and DIR/summary.json (`extra`'s keys added at its top level),
/// prints the report and, when there is no pose, why. `run.stream_diagnostics` is filled from
/// `diagnostics`. Returns the summary as written.
nlohmann::json finishRun(const SlamSystem& system, RunInfo run,
                         const io::StreamDiagnostics& diagnostics, const Trajectory& gt,
                         const RunOutputOptions& options, const nlohmann::json& extra,
                         std::ostream& log);

}  // namespace rgbdi::system
