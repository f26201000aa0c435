// rawlog-convert --info on bags with wheel odometry (checkBagWheels, describeBag): the odometry
// and IMU topics of constructed bags checked as a rawlog's wheel stream is: rate, a gap (count,
// longest, its stamp), wheels moving while the IMU rests, wheels standing while it turns.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/convert/bag_wheel_check.h"
#include "rgbdi/convert/input_description.h"
#include "testing/fixtures.h"

namespace rgbdi::convert {
namespace {

constexpr double kT0 = 100.0;

/// 4 s: IMU at 200 Hz (turning at `imu_turn_rad_s` from 1.5 s to 2.5 s, at rest otherwise),
/// frames at 10 Hz, odometry at 50 Hz (driving at `wheel_speed_m_s` from 1.5 s to 2.5 s,
/// standing otherwise), with no odometry in (3.4 s, 3.6 s).
std::string writeBag(const std::string& path, double imu_turn_rad_s, double wheel_speed_m_s) {
  bag::BagWriter w(path, bag::Compression::None);
  double x = 0.0;
  for (int i = 0; i <= 800; ++i) {
    const double since = i * 0.005, t = kT0 + since;
    const bool active = since > 1.5 && since <= 2.5;
    ImuSample s;
    s.t = t;
    s.acc = Eigen::Vector3d(0, 0, 9.81);
    s.gyr = Eigen::Vector3d(0, 0, active ? imu_turn_rad_s : 0.0);
    w.writeImu(s);
    if (i % 4 == 0) {
      if (active) x += wheel_speed_m_s * 0.02;
      WheelOdometrySample o;
      o.t = t + 0.001;
      o.x_m = x;
      o.has_velocities = true;
      if (!(since > 3.4 && since < 3.6)) w.writeOdometry(o);
    }
    if (i % 20 == 0) {
      RgbdFrame f;
      f.t = t;
      f.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(i % 256, 2, 3));
      f.depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(1000));
      w.writeRgbd(f);
    }
  }
  w.close();
  return path;
}

ConversionSettings smallCamera() {
  ConversionSettings s;
  s.calibration.color.width = 32;
  s.calibration.color.height = 24;
  s.calibration.color.fx = s.calibration.color.fy = 30.0;
  s.calibration.color.cx = 16.0;
  s.calibration.color.cy = 12.0;
  return s;
}

TEST(BagWheelCheck, RateGapAndWheelsMovingWhileTheImuRests) {
  const std::string dir = test::makeTempDir("bag_wheel_check");
  const std::string path = writeBag(dir + "/lifted.bag", 0.0, 0.4);
  const io::StreamDiagnostics d = checkBagWheels(path, smallCamera(), {}, {});
  EXPECT_TRUE(d.ok()) << d.error;
  EXPECT_EQ(d.wheel.delivered, 192u);  // 201 readings, 9 in the gap (3.42 .. 3.58 s)
  EXPECT_EQ(d.imu.delivered, 801u);
  EXPECT_NEAR(d.wheel.median_period_s, 0.02, 1e-6);
  EXPECT_EQ(d.wheel.gaps, 1u);
  EXPECT_NEAR(d.wheel.max_gap_s, 0.2, 1e-6);  // 3.401 -> 3.601
  EXPECT_NEAR(d.wheel_max_gap_t, kT0 + 3.401, 1e-6);
  EXPECT_EQ(d.wheel_moving_at_rest, 1u);
  // As for a rawlog (test_wheel_odometry_io): 1 s windows whose wheel speed exceeds 0.05 m/s
  // end from 1.625 s to 3.375 s; the episode spans from the first one's start.
  EXPECT_NEAR(d.wheel_moving_at_rest_s, 2.75, 0.05);
  EXPECT_EQ(d.wheel_still_imu_moving, 0u);
  ASSERT_EQ(d.wheel_warnings.size(), 2u);
  EXPECT_EQ(d.wheel_warnings[0].rfind(path + " record ", 0), 0u) << d.wheel_warnings[0];
  EXPECT_NE(d.wheel_warnings[0].find("wheel odometry moves (up to 0.4"), std::string::npos)
      << d.wheel_warnings[0];
  EXPECT_NE(d.wheel_warnings[1].find("wheel-odometry gap of 0.2000 s between t = 103.401000 s"),
            std::string::npos)
      << d.wheel_warnings[1];

  const InputDescription info = describeBag(path, smallCamera(), {});
  EXPECT_NE(info.text.find("  odometry      /odom\n"), std::string::npos) << info.text;
  EXPECT_NE(info.text.find("Wheel odometry /odom checked against the IMU /camera/imu:\n"
                           "Wheel: 192 readings, 4.000 s, "),
            std::string::npos)
      << info.text;
  EXPECT_NE(info.text.find("gaps 1 (limit 0.0500 s, largest dt 0.2000 s after t = 103.401000 s)"),
            std::string::npos)
      << info.text;
  EXPECT_NE(info.text.find("moving while the IMU is at rest: 1 times"), std::string::npos)
      << info.text;
  EXPECT_NE(info.text.find("Wheel warnings: 2\n"), std::string::npos) << info.text;
  EXPECT_NE(info.json.find("\"still_imu_moving\": 0"), std::string::npos) << info.json;
  EXPECT_NE(info.json.find("\"moving_at_rest\": 1"), std::string::npos) << info.json;

  // --odom-topic none: no wheel section.
  bag::TopicOverrides none;
  none.odometry = "none";
  const InputDescription without = describeBag(path, smallCamera(), none);
  EXPECT_EQ(without.text.find("Wheel"), std::string::npos) << without.text;
}

TEST(BagWheelCheck, WheelsStandingWhileTheImuTurns) {
  const std::string dir = test::makeTempDir("bag_wheel_check_still");
  const std::string path = writeBag(dir + "/blocked.bag", 0.3, 0.0);
  const io::StreamDiagnostics d = checkBagWheels(path, smallCamera(), {}, {});
  EXPECT_EQ(d.wheel_moving_at_rest, 0u);
  EXPECT_EQ(d.wheel_still_imu_moving, 1u);
  // 1 s windows whose mean rate exceeds 0.1 rad/s end from 1.833 s to 3.167 s.
  EXPECT_NEAR(d.wheel_still_imu_moving_s, 3.167 - 0.833, 0.05);
  // Thresholds from [stream]: above the turn's rate, no finding.
  io::StreamConfig lenient;
  lenient.stream.wheel_still_gyr_rad_s = 0.31;
  EXPECT_EQ(checkBagWheels(path, smallCamera(), {}, lenient).wheel_still_imu_moving, 0u);
}

}  // namespace
}  // namespace rgbdi::convert
