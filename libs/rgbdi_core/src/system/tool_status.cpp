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

}  // namespace rgbdi::system
