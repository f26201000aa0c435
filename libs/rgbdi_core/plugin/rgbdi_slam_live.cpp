// librgbdi_slam_live.so: the `rgbdi-slam --live` run (system::runLive and MRPT's sensor
// framework), loaded by rgbdi-slam only when --live is given (rgbdi/system/live_module.h).
#include <ostream>
#include <type_traits>

#include "rgbdi/system/live_module.h"
#include "rgbdi/system/tool_status.h"

extern "C" __attribute__((visibility("default"))) int rgbdi_slam_live_main(
    const rgbdi::system::LiveRunOptions& opt, std::ostream& log) {
  return rgbdi::system::runReportingErrors(
      "rgbdi-slam", [&] { return rgbdi::system::liveExitStatus(rgbdi::system::runLive(opt, log)); },
      log);
}

// The entry's type is the one rgbdi-slam calls it through.
static_assert(std::is_same_v<decltype(&rgbdi_slam_live_main), rgbdi::system::LiveMain>);
