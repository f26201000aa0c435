// How rgbdi-slam turns a run's failure into its console message and exit status, shared by the
// offline run (in the executable) and the live run (in the module of live_module.h), so that
// both report errors the same way and no exception crosses the module boundary.
#pragma once

#include <functional>
#include <ostream>

namespace rgbdi::system {

/// Returns what `run` returns. A RunConfigError (bad --config or sensors file) is printed as
/// "TOOL: error: ..." and gives kExitUsage, like a bad option; any other exception is printed the
/// same way and gives kExitError.
int runReportingErrors(const char* tool, const std::function<int()>& run, std::ostream& err);

}  // namespace rgbdi::system
