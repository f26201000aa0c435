// LiveSource end to end on rgbdi's own sensors and on small test sensors: complete in-order
// delivery of a replayed rawlog, image dropping (never IMU) behind a slow consumer, the faults a
// live user meets (unknown driver, missing file, sensor that fails to open, silent camera, IMU
// time jumps and stalls, a failing sensor) and the recording reading back identical.
#include <gtest/gtest.h>
#include <mrpt/hwdrivers/CGenericSensor.h>

#include <atomic>
#include <filesystem>

#include "live_test_data.h"
#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/live/realsense_device.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"

namespace rgbdi::live::testsensors {

/// Appends IMU samples every doProcess (200 Hz stamps on the wall clock) and `frames` RGB-D
/// frames at the first calls, then stays silent on frames (a camera that went away). With
/// `jump_after` > 0, the IMU stamps jump forward by `jump_s` after that many samples; with
/// `pause_after` > 0, the IMU pauses `pause_s` of wall time once.
class TestCamera : public mrpt::hwdrivers::CGenericSensor {
  DEFINE_GENERIC_SENSOR(TestCamera)

 public:
  void doProcess() override {
    const double now = io::toSeconds(mrpt::Clock::now());
    if (pause_after_ > 0 && imu_ == static_cast<std::size_t>(pause_after_) && !paused_) {
      paused_ = true;
      pause_until_ = now + pause_s_;
    }
    if (now < pause_until_) return;
    ImuSample s = test::liveImu(0);
    s.t = now + (jump_after_ > 0 && imu_ >= static_cast<std::size_t>(jump_after_) ? jump_s_ : 0);
    if (s.t <= last_t_) s.t = last_t_ + 1e-4;
    last_t_ = s.t;
    ++imu_;
    appendObservation(io::toMrpt(s, "IMU"));
    if (sent_ < frames_) {
      RgbdFrame f = test::liveFrame(sent_++);
      f.t = now - 1e-3;
      appendObservation(io::toMrpt(f, Eigen::Isometry3d::Identity(), "RGBD"));
    }
  }

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& c,
                                 const std::string& s) override {
    frames_ = static_cast<std::size_t>(c.read_int(s, "frames", 5));
    jump_after_ = c.read_int(s, "jump_after", 0);
    jump_s_ = c.read_double(s, "jump_s", 0.0);
    pause_after_ = c.read_int(s, "pause_after", 0);
    pause_s_ = c.read_double(s, "pause_s", 0.0);
    if (c.read_bool(s, "fail_initialize", false)) fail_ = true;
  }
  void initialize() override {
    if (fail_) throw std::runtime_error("device /dev/test0 is busy");
  }

 private:
  std::size_t frames_ = 5, sent_ = 0, imu_ = 0;
  int jump_after_ = 0, pause_after_ = 0;
  double jump_s_ = 0.0, pause_s_ = 0.0, pause_until_ = 0.0, last_t_ = 0.0;
  bool paused_ = false, fail_ = false;
};

/// Throws from doProcess() after a few calls (a device unplugged mid-run).
class TestBrokenSensor : public mrpt::hwdrivers::CGenericSensor {
  DEFINE_GENERIC_SENSOR(TestBrokenSensor)

 public:
  void doProcess() override {
    if (++calls_ > 3) throw std::runtime_error("USB transfer failed");
    ImuSample s = test::liveImu(0);
    s.t = io::toSeconds(mrpt::Clock::now());
    appendObservation(io::toMrpt(s, "IMU"));
  }

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase&,
                                 const std::string&) override {}

 private:
  int calls_ = 0;
};

}  // namespace rgbdi::live::testsensors

IMPLEMENTS_GENERIC_SENSOR(TestCamera, rgbdi::live::testsensors)
IMPLEMENTS_GENERIC_SENSOR(TestBrokenSensor, rgbdi::live::testsensors)

namespace rgbdi::live {
namespace {

namespace fs = std::filesystem;

struct LiveSourceTest : ::testing::Test {
  static void SetUpTestSuite() {
    testsensors::TestCamera::doRegister();
    testsensors::TestBrokenSensor::doRegister();
  }
  void SetUp() override { dir = test::makeTempDir("live_source"); }

  std::string ini(const std::string& text) { return test::writeFile(dir + "/sensors.ini", text); }

  std::string dir;
};

std::string replayIni(const std::string& extra) {
  return "[global]\nlive_first_frame_timeout_s = 20\n\n[REPLAY]\ndriver = RgbdiRawlogReplay\n"
         "process_rate = 200\nfile = seq.rawlog\n" +
         extra;
}

TEST_F(LiveSourceTest, ReplayAtSpeedOneDeliversEveryMeasurementInOrderWithStampsIntact) {
  std::size_t n_imu = 0, n_frames = 0;
  test::writeLiveRawlog(dir + "/seq.rawlog", 1.5, &n_imu, &n_frames);
  LiveSource src(SensorConfig::fromFile(ini(replayIni("speed = 1.0\nstamps = source\n"))));
  test::CollectingSink sink;
  src.pump(sink);
  EXPECT_TRUE(sink.ended);

  // The offline reading of the same file is the reference, measurement for measurement.
  io::RawlogSource ref(dir + "/seq.rawlog");
  test::CollectingSink expected;
  ref.pump(expected);
  ASSERT_EQ(sink.imu.size(), n_imu);
  ASSERT_EQ(sink.frames.size(), n_frames);
  ASSERT_EQ(sink.stamps.size(), expected.stamps.size());
  for (std::size_t i = 0; i < sink.stamps.size(); ++i)
    ASSERT_EQ(sink.stamps[i], expected.stamps[i]) << "measurement " << i;
  for (std::size_t k = 0; k < n_imu; ++k) {
    EXPECT_EQ(sink.imu[k].acc, expected.imu[k].acc);
    EXPECT_EQ(sink.imu[k].gyr, expected.imu[k].gyr);
  }
  for (std::size_t i = 0; i < n_frames; ++i) {
    EXPECT_EQ(sink.frames[i].index, i);
    EXPECT_EQ(cv::norm(sink.frames[i].rgb, expected.frames[i].rgb, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(sink.frames[i].depth, expected.frames[i].depth, cv::NORM_INF), 0.0);
    EXPECT_EQ(sink.frames[i].cam_color.fx, expected.frames[i].cam_color.fx);
  }
  const LiveStats st = src.stats();
  EXPECT_EQ(st.frames_dropped, 0u);
  EXPECT_EQ(st.imu_rejected + st.frames_rejected, 0u);
  EXPECT_EQ(st.imu_delivered, n_imu);
  EXPECT_EQ(st.frames_delivered, n_frames);
  EXPECT_TRUE(st.error.empty()) << st.error;
  ASSERT_EQ(st.sensors.size(), 1u);
  EXPECT_TRUE(st.sensors[0].ended);
  // Paced: 1.5 s of data at speed 1 cannot be delivered in much less wall time.
  EXPECT_GT(st.wall_duration_s, 1.3);
}

TEST_F(LiveSourceTest, ReplayReStampsOntoTheWallClockKeepingTheSpacing) {
  std::size_t n_imu = 0;
  test::writeLiveRawlog(dir + "/seq.rawlog", 0.5, &n_imu);
  LiveSource src(SensorConfig::fromFile(ini(replayIni("speed = 2.0\nstamps = now\n"))));
  const double before = io::toSeconds(mrpt::Clock::now());
  test::CollectingSink sink;
  src.pump(sink);
  ASSERT_EQ(sink.imu.size(), n_imu);
  EXPECT_GE(sink.imu.front().t, before);
  // At speed 2 the 5 ms IMU spacing becomes 2.5 ms of wall time.
  for (std::size_t k = 1; k < n_imu; ++k)
    EXPECT_NEAR(sink.imu[k].t - sink.imu[k - 1].t, test::kLiveImuDt / 2.0, 1e-6);
  const LiveStats st = src.stats();
  EXPECT_EQ(st.imu_latency.count, n_imu);
  EXPECT_GT(st.imu_latency.max_s, 0.0);
}

TEST_F(LiveSourceTest, RateLimitSkipsTheSameFramesAsTheOfflineReader) {
  std::size_t n_imu = 0, n_frames = 0;
  test::writeLiveRawlog(dir + "/seq.rawlog", 1.0, &n_imu, &n_frames);
  io::StreamConfig stream;
  stream.stream.image_rate_limit_hz = 15.0;  // the replayed camera runs at 30 Hz
  LiveSource src(SensorConfig::fromFile(ini(replayIni("speed = 4.0\nstamps = source\n"))), stream);
  test::CollectingSink sink;
  src.pump(sink);
  io::RawlogSource ref(dir + "/seq.rawlog", stream);
  test::CollectingSink expected;
  ref.pump(expected);
  EXPECT_EQ(sink.imu.size(), n_imu);
  ASSERT_EQ(sink.frames.size(), (n_frames + 1) / 2);
  ASSERT_EQ(expected.frames.size(), sink.frames.size());
  for (std::size_t i = 0; i < sink.frames.size(); ++i) {
    EXPECT_EQ(sink.frames[i].t, expected.frames[i].t) << i;
    EXPECT_EQ(sink.frames[i].index, i);
  }
  EXPECT_EQ(src.diagnostics().frames_rate_limited, n_frames / 2);
  EXPECT_EQ(src.stats().frames_received, sink.frames.size());  // skipped ones never entered
}

TEST_F(LiveSourceTest, SlowConsumerMakesImagesDropNeverImuAndQueuesStayBounded) {
  std::size_t n_imu = 0, n_frames = 0;
  test::writeLiveRawlog(dir + "/seq.rawlog", 2.0, &n_imu, &n_frames);
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_image_queue_len = 2\nlive_imu_queue_len = 100000\n"
          "[REPLAY]\ndriver = RgbdiRawlogReplay\nprocess_rate = 200\nfile = seq.rawlog\n"
          "speed = 2.0\nstamps = source\n")));
  test::CollectingSink sink;
  sink.frame_sleep = std::chrono::milliseconds(60);  // < 17 frames/s against 60 arriving
  src.pump(sink);
  const LiveStats st = src.stats();
  EXPECT_EQ(sink.imu.size(), n_imu);  // every IMU sample
  EXPECT_EQ(st.imu_delivered, n_imu);
  EXPECT_EQ(st.frames_received, n_frames);
  EXPECT_GT(st.frames_dropped, 0u);
  EXPECT_EQ(st.frames_delivered + st.frames_dropped, n_frames);
  EXPECT_EQ(sink.frames.size(), st.frames_delivered);
  EXPECT_LE(st.frame_queue_high_water, 2u);
  EXPECT_LT(st.imu_queue_high_water, n_imu);
  for (std::size_t i = 1; i < sink.stamps.size(); ++i)
    ASSERT_LE(sink.stamps[i - 1], sink.stamps[i]) << "delivery " << i;
}

TEST_F(LiveSourceTest, UnknownDriverNamesTheSectionAndTheClass) {
  try {
    LiveSource src(SensorConfig::fromFile(
        ini("[global]\n[CAM0]\ndriver = CNoSuchCamera\nprocess_rate = 30\n")));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::UnknownDriver);
    EXPECT_EQ(e.section(), "CAM0");
    EXPECT_NE(std::string(e.what()).find("[CAM0]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("CNoSuchCamera"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sensors.ini"), std::string::npos) << e.what();
  }
}

TEST_F(LiveSourceTest, MissingReplayFileNamesTheSectionAndTheFile) {
  try {
    LiveSource src(SensorConfig::fromFile(ini(replayIni(""))));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
    EXPECT_EQ(e.section(), "REPLAY");
    const std::string w = e.what();
    EXPECT_NE(w.find("[REPLAY] (RgbdiRawlogReplay)"), std::string::npos) << w;
    EXPECT_NE(w.find("seq.rawlog: file does not exist"), std::string::npos) << w;
  }
}

TEST_F(LiveSourceTest, SensorThatFailsToInitialiseNamesTheSectionAndTheReason) {
  try {
    LiveSource src(SensorConfig::fromFile(
        ini("[CAM]\ndriver = TestCamera\nprocess_rate = 100\nfail_initialize = true\n")));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
    EXPECT_EQ(e.section(), "CAM");
    const std::string w = e.what();
    EXPECT_NE(w.find("[CAM] (TestCamera): cannot open the sensor: device /dev/test0 is busy"),
              std::string::npos)
        << w;
  }
}

TEST_F(LiveSourceTest, BadSensorKeyNamesFileSectionAndKey) {
  test::writeLiveRawlog(dir + "/seq.rawlog", 0.1);
  try {
    LiveSource src(SensorConfig::fromFile(ini(replayIni("speed = -3\n"))));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
    EXPECT_NE(std::string(e.what()).find("[REPLAY] speed: -3 is out of range"), std::string::npos)
        << e.what();
  }
}

TEST_F(LiveSourceTest, SilentCameraEndsTheStreamWithTheTimeoutErrorAfterDeliveringItsFrames) {
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_camera_timeout_s = 0.3\n[CAM]\ndriver = TestCamera\n"
          "process_rate = 200\nframes = 4\n")));
  test::CollectingSink sink;
  try {
    src.pump(sink);
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::CameraTimeout);
    EXPECT_EQ(e.section(), "CAM");
    const std::string w = e.what();
    EXPECT_NE(w.find("[CAM] (TestCamera): no RGB-D frame for"), std::string::npos) << w;
    EXPECT_NE(w.find("live_camera_timeout_s = 0.30"), std::string::npos) << w;
  }
  EXPECT_TRUE(sink.ended);
  EXPECT_EQ(sink.frames.size(), 4u);
  EXPECT_GT(sink.imu.size(), 0u);
  EXPECT_FALSE(src.stats().error.empty());
}

TEST_F(LiveSourceTest, NoFrameAtAllEndsTheStreamNamingTheSensors) {
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_first_frame_timeout_s = 0.3\n[IMUONLY]\ndriver = TestCamera\n"
          "process_rate = 100\nframes = 0\n")));
  test::CollectingSink sink;
  try {
    src.pump(sink);
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::CameraTimeout);
    EXPECT_NE(std::string(e.what()).find("no RGB-D frame from any sensor ([IMUONLY] TestCamera)"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(LiveSourceTest, ImuTimeJumpIsCountedOnceAndTheStreamGoesOn) {
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_camera_timeout_s = 0.3\nlive_imu_time_jump_s = 0.5\n[CAM]\n"
          "driver = TestCamera\nprocess_rate = 200\nframes = 1000\njump_after = 20\n"
          "jump_s = 2.0\n")));
  std::atomic<bool> stop{false};
  struct StopSink : test::CollectingSink {
    std::atomic<bool>* stop;
    void feedImu(const ImuSample& s) override {
      CollectingSink::feedImu(s);
      if (imu.size() >= 60) *stop = true;
    }
  } sink;
  sink.stop = &stop;
  src.pump(sink, &stop);
  const LiveStats st = src.stats();
  EXPECT_EQ(st.imu_time_jumps, 1u);
  ASSERT_FALSE(st.events.empty());
  EXPECT_NE(st.events.front().find("[CAM] (TestCamera): IMU time jump of 2.0"), std::string::npos)
      << st.events.front();
  EXPECT_TRUE(st.error.empty()) << st.error;
}

TEST_F(LiveSourceTest, ImuStallIsReportedAndTheStreamGoesOn) {
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_imu_stall_s = 0.1\nlive_imu_time_jump_s = 10\n[CAM]\n"
          "driver = TestCamera\nprocess_rate = 200\nframes = 100000\npause_after = 10\n"
          "pause_s = 0.5\n")));
  std::atomic<bool> stop{false};
  struct StopSink : test::CollectingSink {
    std::atomic<bool>* stop;
    void feedImu(const ImuSample& s) override {
      CollectingSink::feedImu(s);
      if (imu.size() >= 30) *stop = true;
    }
  } sink;
  sink.stop = &stop;
  src.pump(sink, &stop);
  const LiveStats st = src.stats();
  EXPECT_GE(st.imu_stalls, 1u);
  bool listed = false;
  for (const auto& e : st.events) listed = listed || e.find("IMU stall") != std::string::npos;
  EXPECT_TRUE(listed);
  EXPECT_TRUE(st.error.empty()) << st.error;
}

TEST_F(LiveSourceTest, SensorFailingWhileRunningEndsTheStreamNamingIt) {
  LiveSource src(
      SensorConfig::fromFile(ini("[BROKEN]\ndriver = TestBrokenSensor\nprocess_rate = 100\n")));
  test::CollectingSink sink;
  try {
    src.pump(sink);
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::SensorFailed);
    EXPECT_NE(std::string(e.what()).find("[BROKEN] (TestBrokenSensor): sensor failed: USB "
                                         "transfer failed"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(sink.imu.size(), 3u);  // everything received before the failure
}

TEST_F(LiveSourceTest, ImuBacklogBeyondItsLimitStopsTheRunAsOverload) {
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_imu_queue_len = 10\n[CAM]\ndriver = TestCamera\nprocess_rate = 200\n"
          "frames = 100000\n")));
  struct SlowSink : test::CollectingSink {
    void feedImu(const ImuSample& s) override {
      CollectingSink::feedImu(s);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));  // 20 samples/s against 200
    }
  } sink;
  try {
    src.pump(sink);
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::Overload);
    EXPECT_NE(std::string(e.what()).find("live_imu_queue_len = 10"), std::string::npos) << e.what();
  }
  const LiveStats st = src.stats();
  EXPECT_EQ(st.imu_delivered, st.imu_received - st.imu_rejected);  // still nothing dropped
  EXPECT_LE(st.imu_queue_high_water, 11u + st.ordering_high_water);
}

TEST_F(LiveSourceTest, RecordedRawlogReadsBackIdentical) {
  test::writeLiveRawlog(dir + "/seq.rawlog", 1.0);
  LiveSource src(SensorConfig::fromFile(ini(replayIni("speed = 4.0\nstamps = source\n"))));
  RecordingOptions rec;
  rec.path = dir + "/recorded.rawlog";
  src.record(rec);
  test::CollectingSink live;
  src.pump(live);
  ASSERT_TRUE(fs::is_directory(dir + "/recorded_Images"));

  io::RawlogSource back(rec.path);
  test::CollectingSink read;
  back.pump(read);
  ASSERT_EQ(read.stamps, live.stamps);
  ASSERT_EQ(read.imu.size(), live.imu.size());
  for (std::size_t k = 0; k < live.imu.size(); ++k) {
    EXPECT_EQ(read.imu[k].acc, live.imu[k].acc);
    EXPECT_EQ(read.imu[k].gyr, live.imu[k].gyr);
  }
  ASSERT_EQ(read.frames.size(), live.frames.size());
  for (std::size_t i = 0; i < live.frames.size(); ++i) {
    EXPECT_EQ(cv::norm(read.frames[i].rgb, live.frames[i].rgb, cv::NORM_INF), 0.0) << i;
    EXPECT_EQ(cv::norm(read.frames[i].depth, live.frames[i].depth, cv::NORM_INF), 0.0) << i;
    EXPECT_EQ(read.frames[i].depth_unit_m, live.frames[i].depth_unit_m);
    EXPECT_EQ(read.frames[i].cam_color.fx, live.frames[i].cam_color.fx);
    EXPECT_EQ(read.frames[i].depth_aligned_to_color, live.frames[i].depth_aligned_to_color);
  }

  // The recording (external images) replays as a live sensor too, with the same content.
  LiveSource again(SensorConfig::fromFile(
      ini("[R]\ndriver = RgbdiRawlogReplay\nprocess_rate = 200\nfile = recorded.rawlog\n"
          "speed = 4.0\nstamps = source\n")));
  test::CollectingSink replayed;
  again.pump(replayed);
  ASSERT_EQ(replayed.stamps, live.stamps);
  for (std::size_t i = 0; i < live.frames.size(); ++i)
    EXPECT_EQ(cv::norm(replayed.frames[i].rgb, live.frames[i].rgb, cv::NORM_INF), 0.0) << i;
}

TEST_F(LiveSourceTest, ReplaysARealSenseSdkBagAsRawlogConvertReadsIt) {
  const std::string bag = test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_camera_timeout_s = 5\n[BAG]\ndriver = RgbdiRawlogReplay\n"
          "process_rate = 100\nstamps = source\nspeed = 5\nfile = " +
          bag + "\n")));
  test::CollectingSink sink;
  src.pump(sink);
  // The fixture: two depth-only frames (the colour image has no depth partner), no IMU.
  ASSERT_EQ(sink.frames.size(), 2u);
  EXPECT_TRUE(sink.imu.empty());
  EXPECT_NEAR(sink.frames[0].t, 360.8151, 5e-5);
  EXPECT_NEAR(sink.frames[1].t, 360.9818, 5e-5);
  EXPECT_EQ(sink.frames[0].depth.cols, 640);
  EXPECT_NEAR(sink.frames[0].cam_depth.fx, 390.43, 0.005);
  EXPECT_FALSE(sink.frames[0].depth_aligned_to_color);
}

TEST_F(LiveSourceTest, BagReplayTakesRawlogConvertsConfigFile) {
  const std::string bag = test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  // rawlog-convert --config cal.ini: a 0.15 s pairing tolerance (the colour image pairs with the
  // first depth image) and the extrinsic for a recording without IMU extrinsics.
  const std::string cal =
      test::writeFile(dir + "/cal.ini",
                      "[convert]\npair_tolerance_s = 0.15 ; [s]\n[extrinsic]\n"
                      "R_body_cam = 0 0 1  -1 0 0  0 -1 0\nt_body_cam_m = 0.01 0.02 0.03\n");
  const convert::ConversionSettings settings = convert::loadConversionSettings(cal, "");
  bag::BagConverter conv(bag, settings.options, bag::BagInputOptions(), settings.calibration);
  test::RecordingSink ref;
  ASSERT_TRUE(conv.run(ref).ok());
  ASSERT_EQ(ref.frames.size(), 2u);
  ASSERT_TRUE(ref.frames[0].hasColor());

  LiveSource src(SensorConfig::fromFile(
      ini("[global]\nlive_camera_timeout_s = 5\n[BAG]\ndriver = RgbdiRawlogReplay\n"
          "process_rate = 100\nstamps = source\nspeed = 5\nconfig = cal.ini\nfile = " +
          bag + "\n")));
  test::CollectingSink sink;
  src.pump(sink);
  ASSERT_EQ(sink.frames.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const RgbdFrame& f = sink.frames[i];
    EXPECT_NEAR(f.t, ref.frames[i].t, 1e-6) << i;
    EXPECT_EQ(f.hasColor(), ref.frames[i].hasColor()) << i;
    ASSERT_TRUE(f.has_source_T_body_cam);
    EXPECT_LT((f.source_T_body_cam.translation() - Eigen::Vector3d(0.01, 0.02, 0.03)).norm(), 1e-9);
    EXPECT_LT((f.T_color_depth.matrix() - ref.frames[i].T_color_depth.matrix()).norm(), 1e-9);
  }
  EXPECT_EQ(cv::norm(sink.frames[0].rgb, ref.frames[0].rgb, cv::NORM_INF), 0.0);
}

TEST_F(LiveSourceTest, BagReplayOnOtherTopicsTakesTheTopicsAndAVinsYaml) {
  // A bag on topics no layout knows, without camera_info: rawlog-convert needs --color-topic
  // ... and --camera-yaml for it; the replay the equivalent keys. Its wheel odometry (found by
  // type, as rawlog-convert finds it) is replayed too.
  bag::BagTopics topics;
  topics.color = "/cam/rgb";
  topics.depth = "/cam/depth";
  topics.imu = "/cam/imu";
  {
    bag::BagWriter w(dir + "/other.bag", bag::Compression::None, topics);
    for (std::size_t k = 0, i = 0; k < 100; ++k) {  // 0.5 s of IMU, 15 frames
      w.writeImu(test::liveImu(k));
      if (i < 15 && test::liveFrame(i).t <= test::liveImu(k).t) w.writeRgbd(test::liveFrame(i++));
      if (k % 10 == 0) {  // 10 readings at 20 Hz
        WheelOdometrySample odo;
        odo.t = test::liveImu(k).t;
        odo.x_m = 0.01 * static_cast<double>(k);
        odo.yaw_rad = 0.002 * static_cast<double>(k);
        w.writeOdometry(odo);
      }
    }
    w.close();
  }
  test::writeFile(dir + "/cam.yaml",
                  "%YAML:1.0\nmodel_type: PINHOLE\nimage_width: 32\nimage_height: 24\n"
                  "projection_parameters:\n   fx: 31.5\n   fy: 31.25\n   cx: 15.5\n   cy: 11.5\n"
                  "extrinsicRotation: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                  "   data: [ 0, 0, 1, -1, 0, 0, 0, -1, 0 ]\n"
                  "extrinsicTranslation: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n"
                  "   data: [ 0.04, 0.05, 0.06 ]\nacc_n: 0.1\ngyr_n: 0.01\nacc_w: 0.0002\n"
                  "gyr_w: 2.0e-5\ng_norm: 9.81\n");
  const std::string keys =
      "color_topic = /cam/rgb\ndepth_topic = /cam/depth\n"
      "imu_topic = /cam/imu\ncamera_yaml = cam.yaml\n";
  LiveSource src(SensorConfig::fromFile(
      ini("[BAG]\ndriver = RgbdiRawlogReplay\nprocess_rate = 200\nstamps = source\n"
          "speed = 2\nfile = other.bag\n" +
          keys)));
  test::CollectingSink sink;
  src.pump(sink);
  EXPECT_EQ(sink.imu.size(), 100u);
  ASSERT_EQ(sink.wheel.size(), 10u);
  EXPECT_NEAR(sink.wheel[9].x_m, 0.9, 1e-12);
  EXPECT_NEAR(sink.wheel[9].yaw_rad, 0.18, 1e-12);
  ASSERT_EQ(sink.frames.size(), 15u);
  for (const RgbdFrame& f : sink.frames) {
    EXPECT_DOUBLE_EQ(f.cam_color.fx, 31.5);
    EXPECT_DOUBLE_EQ(f.cam_color.cy, 11.5);
    EXPECT_TRUE(f.depth_aligned_to_color);
    ASSERT_TRUE(f.has_source_T_body_cam);
    EXPECT_LT((f.source_T_body_cam.translation() - Eigen::Vector3d(0.04, 0.05, 0.06)).norm(), 1e-9);
  }

  // Without the topic keys the bag has no known layout: the error lists its topics.
  try {
    LiveSource none(SensorConfig::fromFile(
        ini("[BAG]\ndriver = RgbdiRawlogReplay\nprocess_rate = 200\nfile = other.bag\n")));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
    EXPECT_NE(std::string(e.what()).find("no colour or depth image topic found"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("/cam/rgb"), std::string::npos) << e.what();
  }
}

TEST_F(LiveSourceTest, BagKeysAreRefusedForARawlogAndBadValuesNameTheKey) {
  test::writeLiveRawlog(dir + "/seq.rawlog", 0.2);
  test::writeFile(dir + "/cal.ini", "[convert]\npair_tolerance_s = 0.1\n");
  const auto openError = [&](const std::string& extra) -> std::string {
    try {
      LiveSource src(SensorConfig::fromFile(ini(replayIni(extra))));
    } catch (const LiveError& e) {
      EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
      EXPECT_EQ(e.section(), "REPLAY");
      return e.what();
    }
    return "";
  };
  // A rawlog carries its calibration: a key that would be ignored is an error.
  const std::string rawlog = openError("config = cal.ini\ncolor_topic = /c\n");
  EXPECT_NE(rawlog.find("[REPLAY] (RgbdiRawlogReplay): cannot open the sensor: config, "
                        "color_topic apply to ROS1 bags only; " +
                        dir + "/seq.rawlog is an MRPT rawlog"),
            std::string::npos)
      << rawlog;
  const std::string aligned = openError("depth_aligned = maybe\n");
  EXPECT_NE(aligned.find("[REPLAY] depth_aligned: 'maybe' is not one of auto|yes|no"),
            std::string::npos)
      << aligned;
  const std::string missing = openError("config = nowhere.ini\n");
  EXPECT_NE(missing.find("[REPLAY] config: "), std::string::npos) << missing;
  EXPECT_NE(missing.find(dir + "/nowhere.ini"), std::string::npos) << missing;
}

TEST_F(LiveSourceTest, ShippedSensorFilesConfigureTheirSensors) {
  const std::string share = test::sourceDir() + "/share/sensors/";
  // Every key of the shipped files is accepted by MRPT's loadConfig and the sensor's own keys;
  // what remains is opening the device (no camera, no demo output here, or no SDK).
  const auto openError = [&](const std::string& name) -> std::string {
    try {
      LiveSource src(SensorConfig::fromFile(share + name));
    } catch (const LiveError& e) {
      EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed) << e.what();
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(openError("simulator.ini"), "");  // builds the 60 s sequence, starts nothing
  if (!realSenseSdkAvailable()) {
    EXPECT_NE(openError("d435i.ini").find("built without librealsense2"), std::string::npos);
  }
  const std::string replay = openError("replay.ini");
  if (!replay.empty()) {
    EXPECT_NE(replay.find("demo_wheeled_slopes/sequence/sequence.rawlog: file does not exist"),
              std::string::npos)
        << replay;
  }
}

TEST_F(LiveSourceTest, StopReadingEndsALiveStreamCleanly) {
  LiveSource src(SensorConfig::fromFile(
      ini("[CAM]\ndriver = TestCamera\nprocess_rate = 200\nframes = 100000\n")));
  std::atomic<bool> stop{false};
  struct StopSink : test::CollectingSink {
    std::atomic<bool>* stop;
    void feedRgbd(const RgbdFrame& f) override {
      CollectingSink::feedRgbd(f);
      if (frames.size() >= 5) *stop = true;
    }
  } sink;
  sink.stop = &stop;
  src.pump(sink, &stop);
  EXPECT_TRUE(sink.ended);
  EXPECT_GE(sink.frames.size(), 5u);
  EXPECT_TRUE(src.stats().error.empty());
}

}  // namespace
}  // namespace rgbdi::live
