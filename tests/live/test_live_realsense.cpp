// RgbdiRealSense without the SDK: a synthetic device (accelerometer 250 Hz, gyro 200 Hz, 30 Hz
// framesets, a calibration with non-coinciding cameras) checks the merge at gyro stamps, the
// observations' intrinsics and poses, and that the keys reach the device; the recorded adapter
// plays the real RealSense SDK fixture bag; a build without librealsense2 says so.
#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>

#include <atomic>
#include <fstream>
#include <thread>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/live/realsense_sensor.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"

namespace rgbdi::live {
namespace {

Eigen::Vector3d accelAt(double t) { return Eigen::Vector3d(0.5 + 2.0 * t, -9.7 + 0.3 * t, 0.1); }
Eigen::Vector3d gyroAt(double t) { return Eigen::Vector3d(0.01 * t, 0.02, -0.03); }

/// Calls the callbacks from the test thread on demand; records the request it was opened with.
class SyntheticDevice : public RealSenseDevice {
 public:
  RealSenseRequest opened;
  RealSenseCalibration calib;
  FramesetCallback on_frameset;
  MotionCallback on_motion;
  std::atomic<bool> done{false};

  SyntheticDevice() {
    calib.color.width = calib.depth.width = 64;
    calib.color.height = calib.depth.height = 48;
    calib.color.fx = calib.color.fy = 60.0;
    calib.color.cx = 32.5;
    calib.color.cy = 24.5;
    calib.depth.fx = calib.depth.fy = 58.0;
    calib.depth.cx = 31.0;
    calib.depth.cy = 23.0;
    // As on a D435: p_color = R p_depth + t, the depth origin 15 mm on the colour camera's +x.
    calib.T_color_depth.translation() = Eigen::Vector3d(0.015, 0.0002, 0.0001);
    calib.T_imu_color.linear() =
        Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    calib.T_imu_color.translation() = Eigen::Vector3d(0.0055, 0.0051, 0.0117);
    calib.has_imu = true;
    calib.depth_aligned = false;
    calib.depth_unit_m = 0.00025;
  }
  std::vector<RealSenseDeviceInfo> enumerate() override { return {{"synthetic", "0", ""}}; }
  RealSenseCalibration open(const RealSenseRequest& r) override {
    opened = r;
    return calib;
  }
  void start(FramesetCallback f, MotionCallback m) override {
    on_frameset = std::move(f);
    on_motion = std::move(m);
  }
  void stop() override {}
  bool finished() const override { return done; }
  std::string error() const override { return ""; }

  /// 0.2 s of data from t0 in stamp order, as a device delivers it: accel every 4 ms, gyro every
  /// 5 ms, frames every 1/30 s.
  void play(double t0) {
    int a = 0, g = 0, f = 0;
    for (;;) {
      const double ta = a <= 50 ? a * 0.004 : 1e9, tg = g < 40 ? g * 0.005 : 1e9;
      const double tf = f < 6 ? f / 30.0 : 1e9;
      if (ta == 1e9 && tg == 1e9 && tf == 1e9) break;
      if (ta <= tg && ta <= tf) {
        on_motion({RealSenseMotion::Kind::Accel, t0 + ta, accelAt(ta)});
        ++a;
      } else if (tg <= tf) {
        on_motion({RealSenseMotion::Kind::Gyro, t0 + tg, gyroAt(tg)});
        ++g;
      } else {
        RealSenseFrameset fs;
        fs.t = t0 + tf;
        fs.number = f;
        fs.rgb = cv::Mat(48, 64, CV_8UC3, cv::Scalar(f, 2 * f, 3 * f));
        fs.depth = cv::Mat(48, 64, CV_16UC1, cv::Scalar(4000 + f));
        on_frameset(std::move(fs));
        ++f;
      }
    }
    done = true;
  }
};

struct Collected {
  std::vector<mrpt::obs::CObservationIMU::Ptr> imu;
  std::vector<mrpt::obs::CObservation3DRangeScan::Ptr> frames;
};

Collected runToEnd(RgbdiRealSense& s) {
  Collected c;
  for (int guard = 0; guard < 100000 && !s.endOfData(); ++guard) {
    s.doProcess();
    for (const auto& [t, o] : s.getObservations()) {
      (void)t;
      if (auto i = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) c.imu.push_back(i);
      if (auto f = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o))
        c.frames.push_back(f);
    }
    if (!s.endOfData()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return c;
}

TEST(RgbdiRealSense, MergesAccelAtGyroStampsAndBuildsObservationsFromTheDeviceCalibration) {
  mrpt::config::CConfigFileMemory cfg(
      "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\nserial = 0421\nemitter_enabled = false\n"
      "color_auto_exposure = false\naccel_hz = 63\ngyro_hz = 400\ncolor_width = 64\n"
      "color_height = 48\ndepth_width = 64\ndepth_height = 48\n");
  RgbdiRealSense s;
  s.loadConfig(cfg, "RS");
  auto dev = std::make_unique<SyntheticDevice>();
  SyntheticDevice* d = dev.get();
  s.setDevice(std::move(dev));
  s.initialize();
  EXPECT_EQ(d->opened.serial, "0421");
  EXPECT_FALSE(d->opened.emitter_enabled);
  EXPECT_FALSE(d->opened.color_auto_exposure);
  EXPECT_TRUE(d->opened.depth_auto_exposure);
  EXPECT_EQ(d->opened.accel_hz, 63);
  EXPECT_EQ(d->opened.gyro_hz, 400);
  EXPECT_EQ(d->opened.color_width, 64);

  const double t0 = 1700000000.0;
  d->play(t0);
  const Collected c = runToEnd(s);

  // Every gyro sample inside the accelerometer span (0 .. 0.2 s) becomes one IMU observation at
  // its own stamp; the accel is interpolated linearly, exact for this linear signal.
  ASSERT_EQ(c.imu.size(), 40u);
  for (std::size_t k = 0; k < c.imu.size(); ++k) {
    const ImuSample m = io::fromMrpt(*c.imu[k]);
    const double dt = k * 0.005;
    EXPECT_NEAR(m.t, t0 + dt, 2e-7);
    EXPECT_LT((m.acc - accelAt(dt)).norm(), 1e-6) << k;
    EXPECT_LT((m.gyr - gyroAt(dt)).norm(), 1e-9) << k;
    EXPECT_EQ(c.imu[k]->sensorLabel, "IMU");
  }
  ASSERT_EQ(c.frames.size(), 6u);
  for (std::size_t i = 0; i < c.frames.size(); ++i) {
    const RgbdFrame f = io::fromMrpt(*c.frames[i], "rs");
    EXPECT_NEAR(f.t, t0 + i / 30.0, 2e-7);
    EXPECT_FALSE(f.depth_aligned_to_color);
    EXPECT_DOUBLE_EQ(f.cam_color.fx, 60.0);
    EXPECT_DOUBLE_EQ(f.cam_depth.fx, 58.0);
    EXPECT_DOUBLE_EQ(f.cam_depth.cx, 31.0);
    EXPECT_NEAR(f.depth_unit_m, 0.00025, 1e-12);
    EXPECT_LT((f.T_color_depth.matrix() - d->calib.T_color_depth.matrix()).norm(), 1e-9);
    ASSERT_TRUE(f.has_source_T_body_cam);
    EXPECT_LT((f.source_T_body_cam.matrix() - d->calib.T_imu_color.matrix()).norm(), 1e-9);
    EXPECT_EQ(f.depth.at<std::uint16_t>(0, 0), 4000 + i);
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(i, 2 * i, 3 * i));
  }
  const RealSenseSensorStats st = s.stats();
  EXPECT_EQ(st.accel, 51u);
  EXPECT_EQ(st.gyro, 40u);
  EXPECT_EQ(st.merge.merged, 40u);
  EXPECT_EQ(st.framesets_dropped, 0u);
}

TEST(RgbdiRealSense, RecordedAdapterPlaysTheRealSenseSdkFixtureBag) {
  const std::string bag = test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  // What rawlog-convert makes of the same bag is the reference.
  bag::BagConverter conv(bag, bag::ConvertOptions(), bag::BagInputOptions(),
                         bag::FallbackCalibration::defaults());
  test::RecordingSink ref;
  conv.run(ref);
  ASSERT_FALSE(ref.frames.empty());

  mrpt::config::CConfigFileMemory cfg(
      "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 100\n"
      "device = recorded\nplayback_file = " +
      bag + "\nstamps = source\nspeed = 10\n");
  RgbdiRealSense s;
  s.loadConfig(cfg, "RS");
  s.initialize();
  const Collected c = runToEnd(s);
  ASSERT_EQ(c.frames.size(), ref.frames.size());
  EXPECT_EQ(c.imu.size(), ref.imus.size());
  for (std::size_t i = 0; i < c.frames.size(); ++i) {
    const RgbdFrame f = io::fromMrpt(*c.frames[i], "rs");
    const RgbdFrame& r = ref.frames[i];
    EXPECT_NEAR(f.t, r.t, 2e-7);
    EXPECT_EQ(f.rgb.size(), r.rgb.size());
    EXPECT_EQ(cv::norm(f.rgb, r.rgb, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(f.depth, r.depth, cv::NORM_INF), 0.0);
    EXPECT_DOUBLE_EQ(f.cam_color.fx, r.cam_color.fx);
    EXPECT_DOUBLE_EQ(f.cam_depth.fx, r.cam_depth.fx);
    EXPECT_NEAR(f.depth_unit_m, r.depth_unit_m, 1e-12);
    EXPECT_EQ(f.depth_aligned_to_color, r.depth_aligned_to_color);
    EXPECT_LT((f.T_color_depth.matrix() - r.T_color_depth.matrix()).norm(), 1e-6);
  }
}

TEST(RgbdiRealSense, RecordedAdapterTakesRawlogConvertsConfigFile) {
  const std::string bag = test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  const std::string dir = test::makeTempDir("rs_config");
  // The colour image is 0.1016 s before the first depth image: a 0.15 s tolerance pairs them
  // (the default 0.02 s does not, RecordedAdapterPlaysTheRealSenseSdkFixtureBag).
  const std::string cal = dir + "/cal.ini";
  std::ofstream(cal) << "[convert]\npair_tolerance_s = 0.15\n";
  const auto play = [&](const std::string& extra) {
    mrpt::config::CConfigFileMemory cfg(
        "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 100\ndevice = recorded\nplayback_file = " +
        bag + "\nstamps = source\nspeed = 10\nconfig = " + cal + "\n" + extra);
    RgbdiRealSense s;
    s.loadConfig(cfg, "RS");
    s.initialize();
    return runToEnd(s);
  };
  const Collected c = play("");
  ASSERT_EQ(c.frames.size(), 2u);
  const RgbdFrame f0 = io::fromMrpt(*c.frames[0], "rs");
  ASSERT_TRUE(f0.hasColor());
  EXPECT_NEAR(f0.t, 360.7135, 5e-5);  // a pair takes the colour stamp
  EXPECT_EQ(f0.rgb.cols, 640);
  EXPECT_FALSE(io::fromMrpt(*c.frames[1], "rs").hasColor());

  // [convert] require_colour drops the depth-only frame, as rawlog-convert does.
  std::ofstream(cal) << "[convert]\npair_tolerance_s = 0.15\nrequire_colour = true\n";
  const Collected strict = play("");
  ASSERT_EQ(strict.frames.size(), 1u);
  EXPECT_TRUE(io::fromMrpt(*strict.frames[0], "rs").hasColor());
}

TEST(RgbdiRealSense, CalibrationKeysAreRefusedWhereTheyDoNotApplyOrAreBad) {
  const std::string dir = test::makeTempDir("rs_config");
  const std::string cal = dir + "/cal.ini";
  std::ofstream(cal) << "[convert]\npair_tolerance_s = 0.1\n";
  const auto configError = [](const std::string& text) -> std::string {
    try {
      LiveSource src(SensorConfig::fromText(text, "rs.ini"));
    } catch (const LiveError& e) {
      EXPECT_EQ(e.kind(), LiveError::Kind::OpenFailed);
      EXPECT_NE(std::string(e.what()).find("[RS] (RgbdiRealSense): invalid configuration"),
                std::string::npos)
          << e.what();
      return e.what();
    }
    return "";
  };
  // The SDK reads the calibration from the device: a config there would be ignored.
  const std::string sdk =
      configError("[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\nconfig = " + cal + "\n");
  EXPECT_NE(sdk.find("[RS] config: applies to device = recorded only"), std::string::npos) << sdk;
  // A bad value in the file names the sensor key, the file and its key.
  std::ofstream(cal) << "[convert]\npair_tolerance_s = -1\n";
  const std::string bad = configError(
      "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\ndevice = recorded\n"
      "playback_file = x.bag\nconfig = " +
      cal + "\n");
  EXPECT_NE(bad.find("[RS] config: "), std::string::npos) << bad;
  EXPECT_NE(bad.find(cal), std::string::npos) << bad;
  EXPECT_NE(bad.find("pair_tolerance_s"), std::string::npos) << bad;
  const std::string missing = configError(
      "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\ndevice = recorded\n"
      "playback_file = x.bag\ncamera_yaml = " +
      dir + "/none.yaml\n");
  EXPECT_NE(missing.find("[RS] camera_yaml: "), std::string::npos) << missing;
  EXPECT_NE(missing.find(dir + "/none.yaml"), std::string::npos) << missing;
}

TEST(RgbdiRealSense, WithoutTheSdkTheCameraAdapterExplainsWhatToDo) {
  if (realSenseSdkAvailable()) GTEST_SKIP() << "built with librealsense2";
  mrpt::config::CConfigFileMemory cfg("[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\n");
  RgbdiRealSense s;
  s.loadConfig(cfg, "RS");
  try {
    s.initialize();
    FAIL() << "no error";
  } catch (const RealSenseError& e) {
    EXPECT_NE(std::string(e.what()).find("built without librealsense2"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("device = recorded"), std::string::npos);
  }
}

TEST(RgbdiRealSense, RecordedAdapterNeedsAPlaybackFile) {
  try {
    LiveSource src(SensorConfig::fromText(
        "[RS]\ndriver = RgbdiRealSense\nprocess_rate = 200\ndevice = recorded\n", "rs.ini"));
    FAIL() << "no error";
  } catch (const LiveError& e) {
    EXPECT_EQ(e.section(), "RS");
    EXPECT_NE(std::string(e.what()).find("[RS] playback_file: missing"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::live
