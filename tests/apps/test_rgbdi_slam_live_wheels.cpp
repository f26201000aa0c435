// rgbdi-slam --live on the simulator sensor of a wheeled robot with [wheel] enable = true
// (doc/wheels.md, doc/live.md): RgbdiSimulator delivers the simulated wheel odometry in real time
// and the estimator fuses it, as it fuses the same readings from a rawlog. A 12 s sequence,
// 320x240 at 10 Hz (the camera of test_rgbdi_slam_live, which a loaded 2-core machine follows in
// real time); RUN_SERIAL in ctest (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "testing/fixtures.h"

using rgbdi::test::binDir;
using rgbdi::test::makeTempDir;
using rgbdi::test::runCommand;

TEST(RgbdiSlamLiveWheels, TheSimulatorsWheelOdometryIsFusedInALiveRun) {
  const std::string dir = makeTempDir("rgbdi_live_wheels");
  // One file for the simulator (camera, default encoders: auto) and for rgbdi-slam (fusion on).
  std::ofstream(dir + "/config.ini") << "[camera]\nwidth = 320\nheight = 240\nfx = 308.3\n"
                                        "fy = 308.3\ncx = 162.1\ncy = 119.7\n"
                                        "[wheel]\nenable = true\n";
  std::ofstream(dir + "/simulator.ini")
      << "[global]\nlive_first_frame_timeout_s = 30\n\n[SIM]\ndriver = RgbdiSimulator\n"
         "process_rate = 200\nprofile = wheeled_circle\nduration_s = 12\nfps = 10\nseed = 1\n"
         "config = config.ini\n";
  const std::string out = dir + "/out";
  std::string log;
  const int rc = runCommand(binDir() + "/rgbdi-slam --live " + dir + "/simulator.ini --config " +
                                dir + "/config.ini --out " + out + " --quiet --no-loop",
                            &log);
  ASSERT_EQ(rc, 0) << log;
  std::ifstream f(out + "/summary.json");
  const nlohmann::json s = nlohmann::json::parse(f);
  EXPECT_EQ(s["live"]["stop_reason"], "end_of_data") << s["live"].dump();

  // Every reading arrived: 12 s at [sim] wheel_rate_hz = 50, both ends included; with the
  // encoder ticks and velocities the simulated robot reports, without a gap.
  const auto& stream = s["stream_diagnostics"]["wheel"];
  EXPECT_EQ(stream["delivered"].get<int>(), 601) << stream.dump();
  EXPECT_EQ(stream["with_encoders"].get<int>(), 601) << stream.dump();
  EXPECT_EQ(stream["gaps"].get<int>(), 0) << stream.dump();
  EXPECT_NEAR(stream["rate_hz"].get<double>(), 50.0, 0.1) << stream.dump();

  // The estimator used them. Measured: 44 intervals used (54 keyframes, 121 frames), scales
  // 1.0038 and 0.9994 (the simulated wheels are exact but for their quantisation).
  const auto& w = s["wheel"];
  EXPECT_GT(w["intervals_used"].get<int>(), 20) << w.dump();
  EXPECT_GT(w["factors_solved"].get<int>(), 0) << w.dump();
  EXPECT_EQ(w["intervals_left_out"]["stream_gap"].get<int>(), 0) << w.dump();
  EXPECT_NEAR(w["scale_forward"].get<double>(), 1.0, 0.02) << w.dump();
  EXPECT_NEAR(w["scale_yaw_rate"].get<double>(), 1.0, 0.02) << w.dump();
}
