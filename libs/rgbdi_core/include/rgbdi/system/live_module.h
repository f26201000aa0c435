// `rgbdi-slam --live` runs in a module loaded on demand (librgbdi_slam_live.so, built next to the
// tools in lib/): MRPT's sensor framework (mrpt-hwdrivers) that live runs need pulls in about 170
// shared libraries (GUI toolkits, video codecs, camera SDKs), which cost every offline run about
// 40 MB of resident memory and half a second of start-up when linked into the executable.
#pragma once

#include <ostream>
#include <string>

#include "rgbdi/system/live_runner.h"

namespace rgbdi::system {

/// The module's entry point (C linkage, name kLiveModuleEntry): runs runLive(opt, log), writes
/// every output, reports errors on `log` as rgbdi-slam does (runReportingErrors) and returns
/// rgbdi-slam's exit status (liveExitStatus). No exception leaves it.
using LiveMain = int (*)(const LiveRunOptions& opt, std::ostream& log);
constexpr const char* kLiveModuleEntry = "rgbdi_slam_live_main";
constexpr const char* kLiveModuleFile = "librgbdi_slam_live.so";
/// Environment variable that names the module file instead of the default place.
constexpr const char* kLiveModuleEnv = "RGBDI_LIVE_MODULE";

/// $RGBDI_LIVE_MODULE when set, else ../lib/librgbdi_slam_live.so relative to the directory of
/// the running executable (the build tree's bin/ and lib/).
std::string liveModulePath();
/// Loads the module once per process and returns its entry; throws UserError naming the file
/// and the dynamic loader's reason when it cannot be loaded.
LiveMain loadLiveModule();

}  // namespace rgbdi::system
