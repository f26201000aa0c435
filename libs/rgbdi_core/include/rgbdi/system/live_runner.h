// One live rgbdi-slam run (`rgbdi-slam --live SENSORS.ini`): the sensors of a sensors INI
// (live::LiveSource) feed the threaded SLAM system in live mode, a progress line shows the live
// state, and the run stops on Ctrl-C / SIGTERM (the caller's stop flag), after `duration_s` of
// wall time, when every finite sensor has ended (a replay), or on a sensor fault (camera gone,
// sensor failure, overload). Then every output is written exactly as an offline run writes it
// (run_common.h), summary.json with a "live" section: per-stage latency (p50, p95, max),
// received / delivered / dropped counts per stream, the stop reason.
// Implemented in src/live_run/ and linked into the live module (live_module.h), not into the
// rgbdi-slam executable.
#pragma once

#include <atomic>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "rgbdi/system/run_common.h"

namespace rgbdi::system {

struct LiveRunOptions {
  std::string sensors_path;  ///< sensors INI (MRPT rawlog-grabber layout, doc/live.md)
  std::string out_dir;       ///< created if missing
  std::string config_path;   ///< rgbdi INI ("" = built-in defaults); [stream] windows apply
  std::string record_path;   ///< "" = no recording; else the received stream as a rawlog
  double duration_s = 0.0;   ///< [s] wall time after which the run stops; 0 = no limit
  bool no_depth = false;     ///< monocular-inertial baseline
  bool no_loop = false;      ///< loop closure off
  bool no_wheels = false;    ///< wheel odometry ignored
  bool quiet = false;        ///< no progress line
  bool save_simplemap = false;
  MapRunOptions map;                        ///< --load-map, --localize-only, --no-save-map
  const std::atomic<bool>* stop = nullptr;  ///< set by Ctrl-C / SIGTERM
};

enum class LiveStopReason {
  EndOfData,     ///< every finite sensor (replay, simulator) reached its end
  Duration,      ///< duration_s elapsed
  Interrupted,   ///< the stop flag was set
  CameraGone,    ///< LiveError::CameraTimeout: no frame for live_camera_timeout_s
  SensorFailed,  ///< LiveError::SensorFailed
  Overload,      ///< LiveError::Overload
};
/// "end_of_data", "duration", "interrupted", "camera_gone", "sensor_failed", "overload".
const char* toString(LiveStopReason reason);
/// True for the three sensor faults (the run ended early; outputs are still written).
bool isFault(LiveStopReason reason);

struct LiveRunResult {
  LiveStopReason stop_reason = LiveStopReason::EndOfData;
  std::string error;       ///< the fault's message ("" unless isFault)
  nlohmann::json summary;  ///< as written to summary.json
};

/// Runs, writes the outputs, returns what happened. Throws UserError when the run cannot start:
/// missing or invalid sensors file, a sensor that fails to open (the message names the INI
/// section and the reason), bad configuration, unwritable output or recording.
LiveRunResult runLive(const LiveRunOptions& opt, std::ostream& log);
/// rgbdi-slam's exit status of a finished live run: kExitError when the stream was refused,
/// kExitDamaged after a sensor fault (outputs written), kExitInterrupted after Ctrl-C / SIGTERM,
/// kExitNoPose when no pose was estimated, else kExitOk (--duration, the end of a replay).
int liveExitStatus(const LiveRunResult& result);

}  // namespace rgbdi::system
