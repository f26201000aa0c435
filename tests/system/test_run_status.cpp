// A run that estimates no pose: the reason names the first missing ingredient (frames, IMU,
// overlapping times) before the odometry's own waits; offlineExitStatus gives it status 4 and
// keeps the statuses of refused, damaged and interrupted runs.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "rgbdi/common/command_line.h"
#include "rgbdi/system/slam_summary.h"
#include "rgbdi/system/tool_status.h"

namespace rgbdi::system {
namespace {

/// Diagnostics of a stream with `frames` colour+depth frames over [img0, img1] s and `imu`
/// samples over [imu0, imu1] s.
nlohmann::json diagnostics(std::size_t frames, std::size_t imu, double img0 = 0.0,
                           double img1 = 10.0, double imu0 = 0.0, double imu1 = 10.0) {
  return {{"unusable", 0},
          {"images", {{"delivered", frames}, {"first_t", img0}, {"last_t", img1}}},
          {"imu", {{"delivered", imu}, {"first_t", imu0}, {"last_t", imu1}}}};
}

TEST(NoPoseReason, NamesTheFirstMissingIngredient) {
  RunInfo run;
  run.stream_diagnostics = diagnostics(0, 0);
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "the input has no colour+depth frame (CObservation3DRangeScan)");

  run.stream_diagnostics["unusable"] = 300;  // e.g. images that cannot be decoded
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "no colour+depth frame could be read: 300 observations were unusable (listed above; "
            "summary.json: stream_diagnostics)");
  // The rawlog without its external images folder: the reader found none to name, the frames'
  // messages say which file of which folder was missing.
  run.input = "/data/seq.rawlog.gz";
  run.stream_diagnostics["images_directory"] = "";
  run.stream_diagnostics["warnings"] = {
      "/data/seq.rawlog.gz record 1: cannot load the observation's images: range image "
      "/data/Images/RGBD_0_depth.bin does not exist (external images folder /data/Images); "
      "skipped"};
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "no colour+depth frame could be read: 300 observations were unusable, the rawlog's "
            "external images folder does not exist (looked for /data/seq_Images and "
            "/data/Images) (listed above; summary.json: stream_diagnostics)");
  run.stream_diagnostics["images_directory"] = "/data/seq_Images";  // found: another cause
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "no colour+depth frame could be read: 300 observations were unusable (listed above; "
            "summary.json: stream_diagnostics)");

  // A stream refused or damaged before its first frame: the error, not "no frame in the input".
  run.stream_diagnostics = diagnostics(0, 0);
  run.read_error = "seq.rawlog records 0-114: ... looks like g units ...; the stream is refused";
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "the input stopped before its first colour+depth frame: seq.rawlog records 0-114: ... "
            "looks like g units ...; the stream is refused");

  run.interrupted = true;
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "stopped (Ctrl-C) before the first colour+depth frame");
  run.read_error.clear();

  run.interrupted = false;
  run.frames = 300;
  run.stream_diagnostics = diagnostics(300, 0);
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "the input has no IMU samples (CObservationIMU): the odometry needs them to start");

  run.stream_diagnostics = diagnostics(300, 2000, 100.0, 110.0, 0.0, 9.5);
  EXPECT_EQ(noPoseReason(run, nlohmann::json::object()),
            "the IMU samples (0.000 .. 9.500 s) and the colour+depth frames (100.000 .. 110.000 "
            "s) do not overlap in time");

  run.stream_diagnostics = diagnostics(300, 2000);
  EXPECT_EQ(noPoseReason(run, {{"moving start: not enough parallax yet", 300}}),
            "the odometry never initialised; it waited for: moving start: not enough parallax "
            "yet (300 frames) (summary.json: initialisation_waits, resets, stream_diagnostics)");
}

TEST(OfflineExitStatus, NoPoseIsFourAndTheOtherStatusesWin) {
  const nlohmann::json ok = {{"stream_diagnostics", {{"refused", false}}}, {"read_error", nullptr}};
  EXPECT_EQ(offlineExitStatus(ok, false), kExitOk);
  EXPECT_EQ(offlineExitStatus(ok, true), kExitInterrupted);

  nlohmann::json no_pose = ok;
  no_pose["no_pose_reason"] = "the input has no IMU samples";
  EXPECT_EQ(kExitNoPose, 4);
  EXPECT_EQ(offlineExitStatus(no_pose, false), kExitNoPose);
  EXPECT_EQ(offlineExitStatus(no_pose, true), kExitInterrupted);  // Ctrl-C stays 130

  nlohmann::json damaged = no_pose;
  damaged["read_error"] = "seq.rawlog record 7: truncated";
  EXPECT_EQ(offlineExitStatus(damaged, false), kExitDamaged);
  EXPECT_EQ(offlineExitStatus(damaged, true), kExitInterrupted);

  nlohmann::json refused = damaged;
  refused["stream_diagnostics"]["refused"] = true;
  EXPECT_EQ(offlineExitStatus(refused, false), kExitError);
  EXPECT_EQ(offlineExitStatus(refused, true), kExitError);
}

}  // namespace
}  // namespace rgbdi::system
