// rawlog-convert of a bag with wheel odometry: the nav_msgs/Odometry readings become
// CObservationOdometry in the rawlog, in time order with the IMU and the frames (IMU, then
// wheel, then frame at equal stamps), and a /tf_static wheel extrinsic becomes OUT.ini [wheel].
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"
#include "testing/tiny_frame.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;

/// The IMU frame in base_link: 0.25 m ahead, 0.05 m left, 0.3 m up, yawed 30 deg.
Eigen::Isometry3d T_base_imu() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()).matrix();
  T.translation() = Eigen::Vector3d(0.25, 0.05, 0.3);
  return T;
}

/// 1 s: 32x24 frames at 10 Hz, IMU at 100 Hz, odometry at 50 Hz on the IMU's stamps.
std::string writeBag(const std::string& dir, bool with_tf) {
  const std::string path = dir + "/in.bag";
  bag::BagWriter w(path, bag::Compression::Lz4);
  if (with_tf) w.writeStaticTransform(50.0, "base_link", "camera_imu_frame", T_base_imu());
  for (int k = 0; k <= 100; ++k) {
    ImuSample s;
    s.t = 50.0 + 0.01 * k;
    s.acc = Eigen::Vector3d(0, 0, 9.8);
    w.writeImu(s);
    if (k % 2 == 0) {
      WheelOdometrySample o;
      o.t = s.t;
      o.x_m = 0.004 * k;
      o.yaw_rad = 0.01 * k;
      o.has_velocities = true;
      o.v_forward_m_s = 0.4;
      o.yaw_rate_rad_s = 1.0;
      w.writeOdometry(o);
    }
    if (k % 10 == 0) w.writeRgbd(test::tinyFrame(s.t, k));
  }
  w.close();
  return path;
}

ConversionRequest request(const std::string& dir, bool with_tf) {
  ConversionRequest q;
  q.input = writeBag(dir, with_tf);
  q.output = dir + "/out.rawlog";
  q.settings.calibration.color.width = 32;
  q.settings.calibration.color.height = 24;
  q.settings.calibration.color.fx = q.settings.calibration.color.fy = 30.0;
  q.settings.calibration.color.cx = 16.0;
  q.settings.calibration.color.cy = 12.0;
  return q;
}

TEST(OdometryConversion, ReadingsInTimeOrderAndTheWheelExtrinsicWritten) {
  const std::string dir = test::makeTempDir("odometry_conversion");
  const ConversionRequest q = request(dir, true);
  const bag::ConversionReport r = convertDataset(q);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.wheel_written, 51u);
  EXPECT_NE(r.text().find("101 IMU observations, 0 ground-truth poses, 51 wheel odometry "
                          "observations"),
            std::string::npos)
      << r.text();

  io::RawlogSource src(q.output);
  src.logging_enable_console_output = false;
  io::Measurement m;
  std::vector<WheelOdometrySample> wheels;
  std::vector<std::pair<double, int>> order;  // (t, 0 IMU / 1 wheel / 2 frame)
  while (src.next(m)) {
    if (const auto* w = std::get_if<WheelOdometrySample>(&m)) {
      wheels.push_back(*w);
      order.emplace_back(w->t, 1);
    } else if (const auto* i = std::get_if<ImuSample>(&m)) {
      order.emplace_back(i->t, 0);
    } else {
      order.emplace_back(std::get<RgbdFrame>(m).t, 2);
    }
  }
  ASSERT_EQ(wheels.size(), 51u);
  ASSERT_EQ(order.size(), 101u + 51u + 11u);
  for (std::size_t i = 1; i < order.size(); ++i)
    EXPECT_LE(order[i - 1], order[i]) << "measurement " << i;  // time, then IMU/wheel/frame
  for (std::size_t i = 0; i < wheels.size(); ++i) {
    EXPECT_NEAR(wheels[i].t, 50.0 + 0.02 * static_cast<double>(i), 1e-6);
    EXPECT_NEAR(wheels[i].x_m, 0.008 * static_cast<double>(i), 1e-15);
    EXPECT_NEAR(wheels[i].yaw_rad, 0.02 * static_cast<double>(i), 1e-14);
    EXPECT_TRUE(wheels[i].has_velocities);
    EXPECT_DOUBLE_EQ(wheels[i].v_forward_m_s, 0.4);
    EXPECT_DOUBLE_EQ(wheels[i].yaw_rate_rad_s, 1.0);
  }

  // OUT.ini [wheel]: base_link in the IMU frame, the inverse of the transform in the bag.
  ASSERT_TRUE(fs::exists(dir + "/out.ini"));
  IniReader ini = IniReader::fromFile(dir + "/out.ini");
  const Eigen::VectorXd R = ini.getVector("wheel", "R_body_wheel", Eigen::VectorXd::Zero(9));
  const Eigen::VectorXd t = ini.getVector("wheel", "t_body_wheel_m", Eigen::VectorXd::Zero(3));
  ASSERT_EQ(R.size(), 9);
  ASSERT_EQ(t.size(), 3);
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) T_body_wheel.linear()(i, j) = R[3 * i + j];
  T_body_wheel.translation() = t;
  EXPECT_TRUE(T_body_wheel.isApprox(T_base_imu().inverse(), 1e-12)) << T_body_wheel.matrix();
  EXPECT_NE(r.text().find(dir + "/out.ini (wheel extrinsic from /tf_static of in.bag)"),
            std::string::npos)
      << r.text();
}

TEST(OdometryConversion, WithoutTfStaticNoConfigurationIsWritten) {
  const std::string dir = test::makeTempDir("odometry_conversion_notf");
  const bag::ConversionReport r = convertDataset(request(dir, false));
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.wheel_written, 51u);
  EXPECT_FALSE(fs::exists(dir + "/out.ini"));
  EXPECT_NE(r.text().find("wheel frame 'base_link' in 'camera_imu_frame': no /tf_static in the "
                          "bag; the configuration's [wheel] R_body_wheel / t_body_wheel_m are "
                          "used"),
            std::string::npos)
      << r.text();
}

}  // namespace
}  // namespace rgbdi::convert
