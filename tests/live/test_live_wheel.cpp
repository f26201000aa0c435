// Wheel odometry on the live path (doc/wheels.md, doc/live.md): RgbdiSimulator delivers the
// simulated encoders' CObservationOdometry with exactly the values and stamps rgbdi-sim writes
// into its rawlog for the same configuration and seed, in the offline stream order; and
// LiveSource takes CObservationOdometry from any MRPT sensor class (here a small odometer
// registered by the test) to the consumer's feedWheel, values intact.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <atomic>
#include <string>
#include <vector>

#include "live_test_data.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/live/simulator_sensor.h"
#include "testing/fixtures.h"

namespace rgbdi::live::testsensors {

/// A robot base driver that knows nothing of rgbdi: builds its CObservationOdometry with MRPT's
/// API only, one reading per doProcess() on the wall clock (`readings` of them), reading k at
/// x = 0.1 k m, y = -0.01 k m, yaw = 0.02 k rad, velocities (0.5, 0.01, 0.1 + 0.001 k), ticks
/// (100 k, 101 k), sensorLabel "BASE".
class TestOdometer : public mrpt::hwdrivers::CGenericSensor {
  DEFINE_GENERIC_SENSOR(TestOdometer)

 public:
  void doProcess() override {
    if (sent_ >= readings_) return;
    auto obs = mrpt::obs::CObservationOdometry::Create();
    obs->sensorLabel = "BASE";
    obs->timestamp = mrpt::Clock::now();
    const double k = static_cast<double>(sent_);
    obs->odometry = mrpt::poses::CPose2D(0.1 * k, -0.01 * k, 0.02 * k);
    obs->hasVelocities = true;
    obs->velocityLocal = mrpt::math::TTwist2D(0.5, 0.01, 0.1 + 0.001 * k);
    obs->hasEncodersInfo = true;
    obs->encoderLeftTicks = static_cast<int32_t>(100 * sent_);
    obs->encoderRightTicks = static_cast<int32_t>(101 * sent_);
    ++sent_;
    appendObservation(obs);
  }

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& c,
                                 const std::string& s) override {
    readings_ = static_cast<std::size_t>(c.read_int(s, "readings", 20));
  }

 private:
  std::size_t readings_ = 20, sent_ = 0;
};

/// IMU at every doProcess() and an RGB-D frame at every 5th, on the wall clock (the camera a
/// live run needs beside the odometer).
class TestWheelCamera : public mrpt::hwdrivers::CGenericSensor {
  DEFINE_GENERIC_SENSOR(TestWheelCamera)

 public:
  void doProcess() override {
    const double now = io::toSeconds(mrpt::Clock::now());
    ImuSample s = test::liveImu(0);
    s.t = now;
    appendObservation(io::toMrpt(s, "IMU"));
    if (calls_++ % 5 == 0) {
      RgbdFrame f = test::liveFrame(frames_++);
      f.t = now;
      appendObservation(io::toMrpt(f, Eigen::Isometry3d::Identity(), "RGBD"));
    }
  }

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase&,
                                 const std::string&) override {}

 private:
  std::size_t calls_ = 0, frames_ = 0;
};

}  // namespace rgbdi::live::testsensors

IMPLEMENTS_GENERIC_SENSOR(TestOdometer, rgbdi::live::testsensors)
IMPLEMENTS_GENERIC_SENSOR(TestWheelCamera, rgbdi::live::testsensors)

namespace rgbdi::live {
namespace {

// A small camera and an encoder model with every part set away from its default (rate, radius
// error, time offset, an event), so that a key the sensor failed to take would show.
const char* const kWheelConfig =
    "[camera]\nwidth = 160\nheight = 120\nfx = 154.15\nfy = 154.17\ncx = 80.5\ncy = 60.0\n"
    "[sim]\nwheel_encoders = auto\nwheel_rate_hz = 40\nwheel_time_offset_s = 0.013\n"
    "wheel_radius_error_left = 0.02\nwheel_events = spin:4:0.5\n";

/// One measurement of a stream: 'i' IMU, 'w' wheel, 'f' frame, and its stamp.
struct Entry {
  char kind;
  double t;
};

/// Records the kind and stamp of every measurement, and the wheel readings.
struct OrderSink : test::CollectingSink {
  std::vector<Entry> order;
  void feedImu(const ImuSample& s) override {
    CollectingSink::feedImu(s);
    order.push_back({'i', s.t});
  }
  void feedRgbd(const RgbdFrame& f) override {
    CollectingSink::feedRgbd(f);
    order.push_back({'f', f.t});
  }
  void feedWheel(const WheelOdometrySample& w) override {
    CollectingSink::feedWheel(w);
    order.push_back({'w', w.t});
  }
};

/// Everything RgbdiSimulator delivers for the [SIM] section `section`, run as fast as it goes
/// (speed 1000, no frame skipped), converted back as the live source converts it; the wheel
/// observations' labels go to `wheel_labels`.
OrderSink simulatorOutput(const std::string& dir, const std::string& section,
                          std::vector<std::string>* wheel_labels = nullptr) {
  mrpt::config::CConfigFile cfg(test::writeFile(dir + "/sensors.ini", section));
  RgbdiSimulator sim;
  sim.loadConfig(cfg, "SIM");
  sim.initialize();
  OrderSink sink;
  while (!sim.endOfData()) {
    sim.doProcess();
    for (const auto& [t, o] : sim.getObservations()) {
      (void)t;
      if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) {
        sink.feedImu(io::fromMrpt(*imu));
      } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
        sink.feedWheel(io::fromMrpt(*odo));
        if (wheel_labels) wheel_labels->push_back(odo->sensorLabel);
      } else if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
        sink.feedRgbd(io::fromMrpt(*scan, "sim"));
      }
    }
  }
  return sink;
}

std::string simSection(const std::string& profile, const std::string& extra) {
  return "[SIM]\ndriver = RgbdiSimulator\nprocess_rate = 200\nprofile = " + profile +
         "\nduration_s = 9\nfps = 5\nseed = 7\nconfig = wheels.ini\nspeed = 1000\n"
         "stamps = source\nmax_frame_lateness_s = 1000\n" +
         extra;
}

TEST(RgbdiSimulatorWheels, OdometryIsExactlyWhatRgbdiSimWritesForTheSameConfiguration) {
  const std::string dir = test::makeTempDir("live_sim_wheels");
  test::writeFile(dir + "/wheels.ini", kWheelConfig);
  for (const std::string profile : {"wheeled_circle", "tracked_slopes"}) {
    SCOPED_TRACE(profile);
    std::string log;
    ASSERT_EQ(test::runCommand(test::binDir() + "/rgbdi-sim --profile " + profile +
                                   " --duration 9 --fps 5 --seed 7 --config " + dir +
                                   "/wheels.ini --out " + dir + "/" + profile,
                               &log),
              0)
        << log;
    io::RawlogSource rawlog(dir + "/" + profile + "/sequence.rawlog");
    OrderSink offline;
    rawlog.pump(offline);

    std::vector<std::string> labels;
    const OrderSink live = simulatorOutput(dir, simSection(profile, ""), &labels);
    // 9 s at 40 Hz, both ends included.
    ASSERT_EQ(offline.wheel.size(), 361u);
    ASSERT_EQ(live.wheel.size(), offline.wheel.size());
    for (std::size_t k = 0; k < live.wheel.size(); ++k) {
      const WheelOdometrySample &a = live.wheel[k], &b = offline.wheel[k];
      ASSERT_EQ(a.t, b.t) << k;
      ASSERT_EQ(a.x_m, b.x_m) << k;
      ASSERT_EQ(a.y_m, b.y_m) << k;
      ASSERT_EQ(a.yaw_rad, b.yaw_rad) << k;
      ASSERT_TRUE(a.has_velocities && b.has_velocities) << k;
      ASSERT_EQ(a.v_forward_m_s, b.v_forward_m_s) << k;
      ASSERT_EQ(a.v_lateral_m_s, b.v_lateral_m_s) << k;
      ASSERT_EQ(a.yaw_rate_rad_s, b.yaw_rate_rad_s) << k;
      ASSERT_TRUE(a.has_encoders && b.has_encoders) << k;
      ASSERT_EQ(a.ticks_left, b.ticks_left) << k;
      ASSERT_EQ(a.ticks_right, b.ticks_right) << k;
      ASSERT_EQ(labels[k], "WHEEL_ODOMETRY") << k;
    }
    // The first reading is stamped 13 ms before the first IMU sample (wheel_time_offset_s), and
    // the whole stream (IMU, wheel, frames) comes in the rawlog's order with its stamps.
    EXPECT_NEAR(live.imu.front().t - live.wheel.front().t, 0.013, 1e-6);
    ASSERT_EQ(live.order.size(), offline.order.size());
    for (std::size_t n = 0; n < live.order.size(); ++n) {
      ASSERT_EQ(live.order[n].kind, offline.order[n].kind) << n;
      ASSERT_EQ(live.order[n].t, offline.order[n].t) << n;
    }
  }
}

TEST(RgbdiSimulatorWheels, EncodersFollowTheKeyAndTheLabelIsConfigurable) {
  const std::string dir = test::makeTempDir("live_sim_wheels_keys");
  test::writeFile(dir + "/wheels.ini", kWheelConfig);
  // The sensor's key replaces [sim] wheel_encoders of the config (auto there).
  EXPECT_TRUE(
      simulatorOutput(dir, simSection("wheeled_circle", "wheel_encoders = off\n")).wheel.empty());
  std::vector<std::string> labels;
  const OrderSink on = simulatorOutput(
      dir, simSection("wheeled_circle", "wheel_encoders = on\nwheel_label = BASE\n"), &labels);
  EXPECT_EQ(on.wheel.size(), 361u);
  ASSERT_FALSE(labels.empty());
  EXPECT_EQ(labels.front(), "BASE");

  mrpt::config::CConfigFile bad(test::writeFile(
      dir + "/bad.ini", simSection("wheeled_circle", "wheel_encoders = sometimes\n")));
  RgbdiSimulator sim;
  try {
    sim.loadConfig(bad, "SIM");
    FAIL() << "wheel_encoders = sometimes was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    // MRPT's loadConfig wraps the message: file, key and value are in it.
    EXPECT_NE(what.find("bad.ini"), std::string::npos) << what;
    EXPECT_NE(what.find("wheel_encoders: 'sometimes' is not one of off|on|auto"), std::string::npos)
        << what;
  }
}

TEST(LiveSourceWheels, OdometryFromAnyMrptSensorClassReachesFeedWheelIntact) {
  testsensors::TestOdometer::doRegister();
  testsensors::TestWheelCamera::doRegister();
  const std::string dir = test::makeTempDir("live_any_odometer");
  const double before = io::toSeconds(mrpt::Clock::now());
  LiveSource src(SensorConfig::fromFile(
      test::writeFile(dir + "/sensors.ini",
                      "[CAM]\ndriver = TestWheelCamera\nprocess_rate = 200\n\n"
                      "[BASE]\ndriver = TestOdometer\nprocess_rate = 50\nreadings = 20\n")));
  std::atomic<bool> stop{false};
  struct StopSink : OrderSink {
    std::atomic<bool>* stop;
    void feedWheel(const WheelOdometrySample& w) override {
      OrderSink::feedWheel(w);
      if (wheel.size() >= 20) *stop = true;
    }
  } sink;
  sink.stop = &stop;
  src.pump(sink, &stop);
  ASSERT_EQ(sink.wheel.size(), 20u);
  for (std::size_t k = 0; k < sink.wheel.size(); ++k) {
    const WheelOdometrySample& w = sink.wheel[k];
    const double kk = static_cast<double>(k);
    EXPECT_GE(w.t, before) << k;
    if (k > 0) {
      EXPECT_GT(w.t, sink.wheel[k - 1].t) << k;
    }
    EXPECT_NEAR(w.x_m, 0.1 * kk, 1e-12) << k;
    EXPECT_NEAR(w.y_m, -0.01 * kk, 1e-12) << k;
    EXPECT_NEAR(w.yaw_rad, 0.02 * kk, 1e-12) << k;
    EXPECT_TRUE(w.has_velocities) << k;
    EXPECT_EQ(w.v_forward_m_s, 0.5) << k;
    EXPECT_EQ(w.v_lateral_m_s, 0.01) << k;
    EXPECT_EQ(w.yaw_rate_rad_s, 0.1 + 0.001 * kk) << k;
    EXPECT_TRUE(w.has_encoders) << k;
    EXPECT_EQ(w.ticks_left, static_cast<std::int32_t>(100 * k)) << k;
    EXPECT_EQ(w.ticks_right, static_cast<std::int32_t>(101 * k)) << k;
  }
  // Delivered in time order with the camera's IMU samples and frames.
  for (std::size_t n = 1; n < sink.order.size(); ++n)
    EXPECT_LE(sink.order[n - 1].t, sink.order[n].t) << n;
  EXPECT_FALSE(sink.imu.empty());
  const LiveStats st = src.stats();
  EXPECT_TRUE(st.error.empty()) << st.error;
  for (const SensorCounts& c : st.sensors) EXPECT_EQ(c.other + c.unusable, 0u) << c.section;
}

}  // namespace
}  // namespace rgbdi::live
