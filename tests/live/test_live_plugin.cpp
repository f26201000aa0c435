// The rgbdi sensor plugin in Debian's own rawlog-grabber: it loads, RgbdiSimulator records a few
// seconds, and the rawlog (with rawlog-grabber's external images) reads back with RawlogSource.
// Also RgbdiSimulator through LiveSource: real-time stamps at the configured rates (IMU, frames
// and the wheeled profile's odometry).
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>

#include <filesystem>

#include "live_test_data.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/live/simulator_sensor.h"
#include "testing/fixtures.h"

namespace rgbdi::live {
namespace {

namespace fs = std::filesystem;

const char* const kSmallCamera =
    "[camera]\nwidth = 160\nheight = 120\nfx = 154.15\nfy = 154.17\ncx = 80.5\ncy = 60.0\n";

std::string simulatorSection(double duration_s) {
  return "[SIM]\ndriver = RgbdiSimulator\nprocess_rate = 200\nprofile = wheeled_circle\n"
         "duration_s = " +
         std::to_string(duration_s) +
         "\nconfig = camera.ini\nseed = 3\nmax_frame_lateness_s = 1000\n";
}

TEST(RgbdiSensorPlugin, LoadsInRawlogGrabberAndRecordsFromTheSimulator) {
  const std::string plugin = test::binDir() + "/../lib/librgbdi_mrpt_sensors.so";
  ASSERT_TRUE(fs::exists(plugin)) << plugin;
  if (test::runCommand("command -v rawlog-grabber") != 0) {
    if (test::inCi()) FAIL() << "rawlog-grabber (Debian package mrpt-apps) is not installed";
    GTEST_SKIP() << "rawlog-grabber (mrpt-apps) not installed";
  }
  const std::string dir = test::makeTempDir("live_plugin");
  test::writeFile(dir + "/camera.ini", kSmallCamera);
  test::writeFile(dir + "/sensors.ini", "[global]\nrawlog_prefix = " + dir +
                                            "/grab\nrawlog_GZ_compress_level = 0\n"
                                            "time_between_launches = 0\n\n" +
                                            simulatorSection(20.0));
  // rawlog-grabber stops when it reads ESC on its input.
  std::string out;
  const int rc = test::runCommand(
      "cd " + dir + " && (sleep 8; printf '\\033') | rawlog-grabber -p " + plugin + " sensors.ini",
      &out);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_EQ(out.find("Exception"), std::string::npos) << out;
  std::string rawlog;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".rawlog") rawlog = e.path().string();
  ASSERT_FALSE(rawlog.empty()) << out;

  io::RawlogSource src(rawlog);
  test::CollectingSink sink;
  src.pump(sink);
  // A few seconds at 200 Hz / 30 Hz (rawlog-grabber keeps the last second in memory).
  EXPECT_GT(sink.imu.size(), 200u);
  EXPECT_GT(sink.frames.size(), 20u);
  EXPECT_GT(sink.wheel.size(), 30u);  // wheeled_circle: the encoders at 50 Hz (wheel_encoders auto)
  EXPECT_EQ(src.diagnostics().unusable, 0u);
  ASSERT_FALSE(sink.frames.empty());
  EXPECT_EQ(sink.frames[0].rgb.cols, 160);
  EXPECT_EQ(sink.frames[0].depth.rows, 120);
  EXPECT_NEAR(src.diagnostics().imu.rate_hz, 200.0, 1.0);
  EXPECT_TRUE(fs::is_directory(src.imagesDirectory())) << src.imagesDirectory();
}

TEST(RgbdiSimulatorLive, DeliversTheSimulatorInRealTimeOnTheWallClock) {
  const std::string dir = test::makeTempDir("live_sim");
  test::writeFile(dir + "/camera.ini", kSmallCamera);
  const double before = io::toSeconds(mrpt::Clock::now());
  LiveSource src(SensorConfig::fromFile(
      test::writeFile(dir + "/sensors.ini",
                      "[global]\nlive_first_frame_timeout_s = 30\n" + simulatorSection(10.0))));
  std::atomic<bool> stop{false};
  struct StopSink : test::CollectingSink {
    std::atomic<bool>* stop;
    void feedRgbd(const RgbdFrame& f) override {
      CollectingSink::feedRgbd(f);
      if (frames.size() >= 15) *stop = true;
    }
  } sink;
  sink.stop = &stop;
  src.pump(sink, &stop);
  ASSERT_GE(sink.frames.size(), 15u);
  ASSERT_GT(sink.imu.size(), 50u);
  EXPECT_GE(sink.imu.front().t, before);
  for (std::size_t k = 1; k < sink.imu.size(); ++k)
    EXPECT_NEAR(sink.imu[k].t - sink.imu[k - 1].t, 0.005, 1e-6);
  for (std::size_t i = 1; i < sink.frames.size(); ++i)
    EXPECT_NEAR(sink.frames[i].t - sink.frames[i - 1].t, 1.0 / 30.0, 1e-6);
  // The wheel odometry on the same wall clock, at [sim] wheel_rate_hz = 50.
  ASSERT_GT(sink.wheel.size(), 15u);
  EXPECT_GE(sink.wheel.front().t, before);
  EXPECT_NEAR(sink.wheel.front().t, sink.imu.front().t, 1e-6);  // wheel_time_offset_s = 0
  for (std::size_t k = 1; k < sink.wheel.size(); ++k)
    EXPECT_NEAR(sink.wheel[k].t - sink.wheel[k - 1].t, 0.02, 1e-6);
  EXPECT_EQ(sink.frames[0].rgb.cols, 160);
  const LiveStats st = src.stats();
  EXPECT_TRUE(st.error.empty()) << st.error;
  EXPECT_EQ(st.frame_latency.count, st.frames_delivered);
}

TEST(RgbdiSimulatorLive, SkipsFramesItWouldRenderTooLateAndNothingElse) {
  const std::string dir = test::makeTempDir("live_sim_skip");
  test::writeFile(dir + "/camera.ini", kSmallCamera);
  // At 50x real time a frame is due every 0.7 ms, faster than it renders.
  const auto run = [&](double lateness_s, std::size_t& imu, std::size_t& frames) {
    mrpt::config::CConfigFile cfg(test::writeFile(
        dir + "/s.ini", simulatorSection(10.0) + "speed = 50\nmax_frame_lateness_s = " +
                            std::to_string(lateness_s) + "\n"));
    RgbdiSimulator sim;
    sim.loadConfig(cfg, "SIM");
    sim.initialize();
    imu = frames = 0;
    while (!sim.endOfData()) {
      sim.doProcess();
      for (const auto& [t, o] : sim.getObservations()) {
        (void)t;
        if (std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) ++imu;
        if (std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) ++frames;
      }
    }
    return sim.framesSkipped();
  };
  std::size_t imu_all = 0, frames_all = 0, imu_late = 0, frames_late = 0;
  EXPECT_EQ(run(1000.0, imu_all, frames_all), 0u);
  const std::size_t skipped = run(0.0, imu_late, frames_late);
  EXPECT_GT(skipped, 0u);
  EXPECT_EQ(frames_late + skipped, frames_all);
  EXPECT_EQ(imu_late, imu_all);  // IMU samples are never skipped
  EXPECT_EQ(imu_all, 2001u);     // 10 s at 200 Hz, both ends included
}

}  // namespace
}  // namespace rgbdi::live
