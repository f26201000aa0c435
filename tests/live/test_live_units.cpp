// The small pieces of the live stage with exact answers: the sensors INI parser, the latency
// histogram and the playback clock.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>

#include <string>
#include <vector>

#include "rgbdi/live/latency_histogram.h"
#include "rgbdi/live/playback_clock.h"
#include "rgbdi/live/sensor_config.h"
#include "testing/fixtures.h"

namespace rgbdi::live {
namespace {

std::string configError(const std::string& text) {
  try {
    SensorConfig::fromText(text, "s.ini");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(SensorConfig, ReadsSensorSectionsInFileOrderAndTheLiveKeysOfGlobal) {
  const SensorConfig c = SensorConfig::fromText(
      "[global]\nrawlog_prefix = ./x\nrawlog_GZ_compress_level = 0\nlive_image_queue_len = 5\n"
      "live_camera_timeout_s = 1.5\n\n[CAM]\ndriver = RgbdiRealSense\nprocess_rate = 200\n"
      "serial = 123\n\n[OLD]\ndriver = CKinect\nprocess_rate = 30\nrawlog-grabber-ignore = true\n"
      "\n[IMU]\ndriver = CIMUXSens_MT4\nprocess_rate = 400.5\n",
      "s.ini");
  ASSERT_EQ(c.sensors.size(), 2u);
  EXPECT_EQ(c.sensors[0].name, "CAM");
  EXPECT_EQ(c.sensors[0].driver, "RgbdiRealSense");
  EXPECT_EQ(c.sensors[0].process_rate_hz, 200.0);
  EXPECT_EQ(c.sensors[1].name, "IMU");
  EXPECT_EQ(c.sensors[1].process_rate_hz, 400.5);
  EXPECT_EQ(c.live.image_queue_len, 5);
  EXPECT_EQ(c.live.camera_timeout_s, 1.5);
  EXPECT_EQ(c.live.imu_queue_len, LiveOptions().imu_queue_len);
}

TEST(SensorConfig, MissingDriverOrRateNamesTheSectionAndKey) {
  EXPECT_NE(configError("[CAM]\nprocess_rate = 30\n").find("s.ini [CAM] driver: missing"),
            std::string::npos);
  EXPECT_NE(configError("[CAM]\ndriver = X\n").find("s.ini [CAM] process_rate: missing"),
            std::string::npos);
  EXPECT_NE(configError("[CAM]\ndriver = X\nprocess_rate = 0\n").find("[CAM] process_rate"),
            std::string::npos);
}

TEST(SensorConfig, RejectsAFileWithoutSensorsAndUnknownGlobalKeys) {
  EXPECT_NE(configError("[global]\nrawlog_prefix = x\n").find("no sensor section"),
            std::string::npos);
  const std::string typo = configError(
      "[global]\nlive_camera_timeout = 3\n[A]\ndriver = X\n"
      "process_rate = 1\n");
  EXPECT_NE(typo.find("live_camera_timeout"), std::string::npos) << typo;
  EXPECT_NE(configError("[global]\nlive_image_queue_len = 0\n[A]\ndriver = X\nprocess_rate = 1\n")
                .find("live_image_queue_len"),
            std::string::npos);
}

TEST(SensorConfig, ShippedSensorFilesAreValid) {
  for (const char* name : {"d435i", "replay", "simulator"}) {
    const SensorConfig c =
        SensorConfig::fromFile(test::sourceDir() + "/share/sensors/" + name + ".ini");
    ASSERT_EQ(c.sensors.size(), 1u) << name;
    EXPECT_EQ(c.sensors[0].process_rate_hz, 200.0) << name;
  }
  EXPECT_EQ(
      SensorConfig::fromFile(test::sourceDir() + "/share/sensors/d435i.ini").sensors[0].driver,
      "RgbdiRealSense");
}

TEST(SensorConfig, ShippedFilesGiveRawlogGrabbersStringKeysWithoutTheirComments) {
  // MRPT's reader (rawlog-grabber's) keeps a trailing "; comment" in a string value: a comment
  // after rawlog_prefix named the recording "./x_grab       ; output rawlog name prefix_DATE".
  for (const char* name : {"d435i", "replay", "simulator"}) {
    const mrpt::config::CConfigFile cfg(test::sourceDir() + "/share/sensors/" + name + ".ini");
    std::vector<std::string> sections;
    cfg.getAllSections(sections);
    for (const std::string& sec : sections)
      for (const char* key : {"rawlog_prefix", "driver", "sensorLabel", "external_images_format"})
        if (cfg.keyExists(sec, key)) {
          const std::string v = cfg.read_string(sec, key, "");
          EXPECT_EQ(v.find_first_of(";#"), std::string::npos) << name << " [" << sec << "] " << v;
          EXPECT_FALSE(v.empty()) << name << " [" << sec << "] " << key;
        }
    EXPECT_EQ(cfg.read_string("global", "rawlog_prefix", ""), std::string("./") + name + "_grab");
  }
}

TEST(LatencyHistogram, PercentilesAreTheUpperBinEdgeAndTheMaximumIsExact) {
  LatencyHistogram h(0.001, 1.0);
  for (int i = 1; i <= 100; ++i) h.add(i * 0.001 - 0.0005);  // one value in each of 100 bins
  const LatencySummary s = h.summary();
  EXPECT_EQ(s.count, 100u);
  EXPECT_DOUBLE_EQ(s.p50_s, 0.050);
  EXPECT_DOUBLE_EQ(s.p95_s, 0.095);
  EXPECT_DOUBLE_EQ(s.max_s, 0.0995);
  EXPECT_DOUBLE_EQ(h.quantile(1.0), 0.0995);  // clamped to the maximum
}

TEST(LatencyHistogram, ValuesBeyondTheRangeLandInTheLastBinAndNegativesInTheFirst) {
  LatencyHistogram h(0.01, 0.1);
  h.add(-0.5);
  h.add(7.0);
  EXPECT_DOUBLE_EQ(h.quantile(0.5), 0.01);
  EXPECT_DOUBLE_EQ(h.summary().max_s, 7.0);
  EXPECT_DOUBLE_EQ(h.quantile(1.0), 0.1);
  EXPECT_THROW(LatencyHistogram(0.0, 1.0), std::invalid_argument);
}

TEST(PlaybackClock, MapsWallTimeToDataTimeAtTheGivenSpeed) {
  PlaybackClock c(2.0, false);
  c.start(5000.0, 100.0);
  EXPECT_DOUBLE_EQ(c.horizon(5000.0), 100.0);
  EXPECT_DOUBLE_EQ(c.horizon(5001.5), 103.0);
  EXPECT_DOUBLE_EQ(c.dueWall(104.0), 5002.0);
  EXPECT_DOUBLE_EQ(c.outputStamp(104.0), 104.0);
  PlaybackClock r(0.5, true);
  r.start(5000.0, 100.0);
  EXPECT_DOUBLE_EQ(r.outputStamp(101.0), 5002.0);
  EXPECT_THROW(PlaybackClock(0.0, true), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::live
