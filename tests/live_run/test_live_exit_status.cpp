// liveExitStatus: a live run that estimated no pose ends with status 4 when it stopped normally
// (--duration, end of a replay); a refused stream, a sensor fault and Ctrl-C keep their status.
#include <gtest/gtest.h>

#include "rgbdi/common/command_line.h"
#include "rgbdi/system/live_runner.h"

namespace rgbdi::system {
namespace {

LiveRunResult result(LiveStopReason reason, bool no_pose) {
  LiveRunResult r;
  r.stop_reason = reason;
  r.summary = {{"stream_diagnostics", {{"refused", false}}}};
  if (no_pose) r.summary["no_pose_reason"] = "the input has no IMU samples";
  return r;
}

TEST(LiveExitStatus, NoPoseIsFourAfterANormalStopOnly) {
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::Duration, false)), kExitOk);
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::EndOfData, false)), kExitOk);
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::Duration, true)), kExitNoPose);
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::EndOfData, true)), kExitNoPose);
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::Interrupted, true)), kExitInterrupted);
  EXPECT_EQ(liveExitStatus(result(LiveStopReason::CameraGone, true)), kExitDamaged);
  LiveRunResult refused = result(LiveStopReason::EndOfData, true);
  refused.summary["stream_diagnostics"]["refused"] = true;
  EXPECT_EQ(liveExitStatus(refused), kExitError);
}

}  // namespace
}  // namespace rgbdi::system
