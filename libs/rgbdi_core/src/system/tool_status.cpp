#include "rgbdi/system/tool_status.h"

#include <exception>

#include "rgbdi/common/command_line.h"
#include "rgbdi/system/run_common.h"

namespace rgbdi::system {

int runReportingErrors(const char* tool, const std::function<int()>& run, std::ostream& err) {
  try {
    return run();
  } catch (const RunConfigError& e) {
    err << tool << ": error: " << e.what() << "\n";
    return kExitUsage;  // a configuration error, like a bad option
  } catch (const std::exception& e) {
    err << tool << ": error: " << e.what() << "\n";
    return kExitError;
  }
}

int offlineExitStatus(const nlohmann::json& summary, bool stopped) {
  if (summary.contains("stream_diagnostics") && summary["stream_diagnostics"].is_object() &&
      summary["stream_diagnostics"].value("refused", false))
    return kExitError;                   // nothing usable was delivered
  if (stopped) return kExitInterrupted;  // the outputs of the part processed are written
  if (summary.contains("read_error") && !summary["read_error"].is_null()) return kExitDamaged;
  if (summary.contains("no_pose_reason")) return kExitNoPose;
  return kExitOk;
}

}  // namespace rgbdi::system
