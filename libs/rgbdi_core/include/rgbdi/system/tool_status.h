// How rgbdi-slam turns a run's failure into its console message and exit status, shared by the
// offline run (in the executable) and the live run (in the module of live_module.h), so that
// both report errors the same way and no exception crosses the module boundary.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <ostream>

namespace rgbdi::system {

/// Returns what `run` returns. A RunConfigError (bad --config or sensors file) is printed as
/// "TOOL: error: ..." and gives kExitUsage, like a bad option; any other exception is printed the
/// same way and gives kExitError.
int runReportingErrors(const char* tool, const std::function<int()>& run, std::ostream& err);

/// The exit status of a finished --input run from its summary.json content and whether Ctrl-C /
/// SIGTERM stopped it: kExitError when the stream was refused (nothing delivered);
/// kExitInterrupted when stopped; kExitDamaged when the input ended in damage; kExitNoPose when
/// no pose was estimated ("no_pose_reason"); else kExitOk. The first that applies wins, so a
/// stopped or damaged run keeps its status whatever it estimated.
int offlineExitStatus(const nlohmann::json& summary, bool stopped);

}  // namespace rgbdi::system
