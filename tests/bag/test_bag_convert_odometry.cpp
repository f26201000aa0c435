// Wheel odometry in ROS1 bags: nav_msgs/Odometry found by type or named (--odom-topic, none),
// decoded into the readings rgbdi's rawlog reader takes from a CObservationOdometry (x, y, yaw of
// the quaternion, velocities), bad messages (truncated, other definition, non-finite, stamps
// going back) named and skipped; /tf_static composed into T_body_wheel.
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstring>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_layout.h"
#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/bag/ros_odometry.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"
#include "testing/tiny_frame.h"

namespace rgbdi::bag {

/// Bytes written as they are under the type nav_msgs/Odometry with the md5sum `Md5`: a truncated
/// message, or a message of another definition of the same name.
template <int Md5>
struct RawOdometry {
  std::vector<std::uint8_t> bytes;
};

}  // namespace rgbdi::bag

namespace ros::message_traits {
template <int Md5>
struct MD5Sum<rgbdi::bag::RawOdometry<Md5>> {
  static const char* value() {
    return Md5 == 0 ? MD5Sum<nav_msgs::Odometry>::value() : "0123456789abcdef0123456789abcdef";
  }
  static const char* value(const rgbdi::bag::RawOdometry<Md5>&) { return value(); }
};
template <int Md5>
struct DataType<rgbdi::bag::RawOdometry<Md5>> {
  static const char* value() { return "nav_msgs/Odometry"; }
  static const char* value(const rgbdi::bag::RawOdometry<Md5>&) { return value(); }
};
template <int Md5>
struct Definition<rgbdi::bag::RawOdometry<Md5>> {
  static const char* value() { return Definition<nav_msgs::Odometry>::value(); }
  static const char* value(const rgbdi::bag::RawOdometry<Md5>&) { return value(); }
};
}  // namespace ros::message_traits

namespace ros::serialization {
template <int Md5>
struct Serializer<rgbdi::bag::RawOdometry<Md5>> {
  template <typename Stream>
  static void write(Stream& s, const rgbdi::bag::RawOdometry<Md5>& m) {
    if (!m.bytes.empty()) std::memcpy(s.advance(m.bytes.size()), m.bytes.data(), m.bytes.size());
  }
  template <typename Stream>
  static void read(Stream&, rgbdi::bag::RawOdometry<Md5>&) {}
  static std::uint32_t serializedLength(const rgbdi::bag::RawOdometry<Md5>& m) {
    return static_cast<std::uint32_t>(m.bytes.size());
  }
};
}  // namespace ros::serialization

namespace rgbdi::bag {
namespace {

template <typename M>
std::vector<std::uint8_t> serialize(const M& msg) {
  std::vector<std::uint8_t> buf(ros::serialization::serializationLength(msg));
  ros::serialization::OStream s(buf.data(), static_cast<std::uint32_t>(buf.size()));
  ros::serialization::serialize(s, msg);
  return buf;
}

nav_msgs::Odometry odometry(double t, double x, double y, double yaw) {
  nav_msgs::Odometry m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = "odom";
  m.child_frame_id = "base_link";
  m.pose.pose.position.x = x;
  m.pose.pose.position.y = y;
  m.pose.pose.orientation.z = std::sin(0.5 * yaw);
  m.pose.pose.orientation.w = std::cos(0.5 * yaw);
  m.twist.twist.linear.x = 0.5;
  m.twist.twist.linear.y = -0.01;
  m.twist.twist.angular.z = 0.2;
  return m;
}

std::vector<BagTopic> cameraTopics() {
  return {{"/camera/aligned_depth_to_color/image_raw", "sensor_msgs/Image", 10},
          {"/camera/color/image_raw", "sensor_msgs/Image", 10},
          {"/camera/imu", "sensor_msgs/Imu", 100}};
}

FallbackCalibration smallCamera() {
  FallbackCalibration cal = FallbackCalibration::defaults();
  cal.color.width = 32;
  cal.color.height = 24;
  cal.color.fx = cal.color.fy = 30.0;
  cal.color.cx = 16.0;
  cal.color.cy = 12.0;
  cal.color_source = "test";
  return cal;
}

/// 1 s of 32x24 frames at 10 Hz, IMU at 100 Hz, odometry at 50 Hz (reading k at 50 + 0.02 k:
/// x = 0.01 k, y = 0.002 k, yaw = 0.03 k - 1, wrapping through pi at the end), except reading
/// `nan_at` with a NaN x.
std::string writeBag(const std::string& path, int nan_at, bool with_tf) {
  BagWriter w(path, Compression::None);
  if (with_tf) {
    // The IMU sits 0.1 m ahead of and 0.2 m above base_link, turned 90 deg about z; the chain
    // goes base_link -> camera_link -> camera_imu_frame.
    Eigen::Isometry3d T_base_camera = Eigen::Isometry3d::Identity();
    T_base_camera.translation() = Eigen::Vector3d(0.1, 0.0, 0.2);
    Eigen::Isometry3d T_camera_imu = Eigen::Isometry3d::Identity();
    T_camera_imu.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
    w.writeStaticTransform(50.0, "base_link", "camera_link", T_base_camera);
    w.writeStaticTransform(50.0, "camera_link", "camera_imu_frame", T_camera_imu);
  }
  for (int k = 0; k <= 100; ++k) {
    ImuSample s;
    s.t = 50.0 + 0.01 * k;
    s.acc = Eigen::Vector3d(0, 0, 9.8);
    w.writeImu(s);
    if (k % 2 == 0) {
      const int i = k / 2;
      WheelOdometrySample o;
      o.t = s.t;
      o.x_m = i == nan_at ? std::nan("") : 0.01 * i;
      o.y_m = 0.002 * i;
      o.yaw_rad = std::remainder(0.03 * i - 1.0 + 2.5, 2 * M_PI);
      o.has_velocities = true;
      o.v_forward_m_s = 0.5;
      o.yaw_rate_rad_s = 1.5;
      w.writeOdometry(o);
    }
    if (k % 10 == 0) w.writeRgbd(test::tinyFrame(s.t, k));
  }
  w.close();
  return path;
}

TEST(BagOdometryLayout, FoundByTypeNamedOrLeftOut) {
  std::vector<BagTopic> t = cameraTopics();
  t.push_back({"/wheels/odom", "nav_msgs/Odometry", 50});
  BagLayout l = resolveBagLayout(t, {}, std::nullopt, "w.bag");
  EXPECT_EQ(l.kind, BagLayoutKind::Dataset);  // odometry does not make the layout custom
  EXPECT_EQ(l.odometry, "/wheels/odom");
  EXPECT_EQ(l.streamedTopics().size(), 4u);
  EXPECT_TRUE(l.tf_static.empty());

  TopicOverrides none;
  none.odometry = "none";
  l = resolveBagLayout(t, none, std::nullopt, "w.bag");
  EXPECT_TRUE(l.odometry.empty());
  EXPECT_EQ(l.streamedTopics().size(), 3u);

  // Two odometry topics: an error naming both, unless one is named.
  t.push_back({"/ekf/odom", "nav_msgs/Odometry", 50});
  t.push_back({"/tf_static", "tf2_msgs/TFMessage", 1});
  try {
    resolveBagLayout(t, {}, std::nullopt, "w.bag");
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    EXPECT_STREQ(e.what(),
                 "w.bag: several nav_msgs/Odometry topics (/ekf/odom, /wheels/odom): name the "
                 "wheel odometry with --odom-topic TOPIC, or leave it out with --odom-topic none");
  }
  TopicOverrides named;
  named.odometry = "/wheels/odom";
  l = resolveBagLayout(t, named, std::nullopt, "w.bag");
  EXPECT_EQ(l.odometry, "/wheels/odom");
  EXPECT_EQ(l.tf_static, "/tf_static");
  EXPECT_TRUE(resolveBagLayout(t, none, std::nullopt, "w.bag").odometry.empty());

  TopicOverrides wrong;
  wrong.odometry = "/camera/imu";
  try {
    resolveBagLayout(t, wrong, std::nullopt, "w.bag");
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    EXPECT_STREQ(e.what(),
                 "w.bag: odometry topic '/camera/imu' has type sensor_msgs/Imu, expected "
                 "nav_msgs/Odometry");
  }
}

TEST(BagOdometryLayout, AnotherDefinitionOfTheTypeIsRefused) {
  std::vector<BagTopic> t = cameraTopics();
  t.push_back({"/odom", "nav_msgs/Odometry", 5, "0123456789abcdef0123456789abcdef"});
  try {
    resolveBagLayout(t, {}, std::nullopt, "w.bag");
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    EXPECT_STREQ(e.what(),
                 "w.bag: odometry topic '/odom' has message definition md5sum "
                 "0123456789abcdef0123456789abcdef, expected cd5e73d190d741a2f92e81eda573aca7 "
                 "(nav_msgs/Odometry of ROS1); leave it out with --odom-topic none");
  }
  t.back().md5sum = ros::message_traits::MD5Sum<nav_msgs::Odometry>::value();
  EXPECT_EQ(resolveBagLayout(t, {}, std::nullopt, "w.bag").odometry, "/odom");
}

TEST(RosOdometry, PlanarReadingOfA3dPose) {
  // Yaw 0.7 after pitch 0.2 and roll -0.1 (ZYX): the reading keeps x, y and the yaw.
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()));
  nav_msgs::Odometry m = odometry(12.5, 1.25, -3.5, 0.0);
  m.pose.pose.position.z = 0.4;
  // Not normalised: the yaw is the rotation's.
  m.pose.pose.orientation.x = 2 * q.x();
  m.pose.pose.orientation.y = 2 * q.y();
  m.pose.pose.orientation.z = 2 * q.z();
  m.pose.pose.orientation.w = 2 * q.w();
  const std::vector<std::uint8_t> bytes = serialize(m);
  const nav_msgs::Odometry back =
      deserializeOdometry(bytes.data(), static_cast<std::uint32_t>(bytes.size()), "x");
  EXPECT_EQ(back.child_frame_id, "base_link");
  const WheelOdometrySample w = wheelFromOdometry(back, 12.5, "x");
  EXPECT_DOUBLE_EQ(w.t, 12.5);
  EXPECT_DOUBLE_EQ(w.x_m, 1.25);
  EXPECT_DOUBLE_EQ(w.y_m, -3.5);
  EXPECT_NEAR(w.yaw_rad, 0.7, 1e-14);
  EXPECT_TRUE(w.has_velocities);
  EXPECT_DOUBLE_EQ(w.v_forward_m_s, 0.5);
  EXPECT_DOUBLE_EQ(w.v_lateral_m_s, -0.01);
  EXPECT_DOUBLE_EQ(w.yaw_rate_rad_s, 0.2);
  EXPECT_FALSE(w.has_encoders);
  // A half turn: yaw pi (not -pi), as MRPT's CPose2D wraps.
  EXPECT_DOUBLE_EQ(wheelFromOdometry(odometry(1, 0, 0, M_PI), 1, "x").yaw_rad, M_PI);
}

TEST(RosOdometry, BadMessagesAreNamed) {
  const std::vector<std::uint8_t> bytes = serialize(odometry(1.0, 0, 0, 0));
  // header 4 + 8 + (4 + 4 "odom") = 20, child_frame_id 4 + 9 = 13: the pose starts at 33.
  ASSERT_EQ(bytes.size(), 33u + 43 * 8 + 42 * 8);
  try {
    deserializeOdometry(bytes.data(), 100, "b.bag /odom message 7");
    FAIL() << "expected MessageDecodeError";
  } catch (const MessageDecodeError& e) {
    EXPECT_STREQ(e.what(),
                 "b.bag /odom message 7: corrupt message: pose (PoseWithCovariance) needs 344 "
                 "bytes at offset 33, the message has 67 left (of 100)");
  }
  std::vector<std::uint8_t> long_name = bytes;
  long_name[20] = 0xff;  // child_frame_id length far beyond the message
  EXPECT_THROW(
      deserializeOdometry(long_name.data(), static_cast<std::uint32_t>(long_name.size()), "b"),
      MessageDecodeError);

  nav_msgs::Odometry m = odometry(1.0, 0, 0, 0);
  m.twist.twist.angular.z = std::numeric_limits<double>::infinity();
  try {
    wheelFromOdometry(m, 1.0, "b.bag /odom message 3 (stamp 1.000000 s)");
    FAIL() << "expected MessageDecodeError";
  } catch (const MessageDecodeError& e) {
    EXPECT_STREQ(e.what(),
                 "b.bag /odom message 3 (stamp 1.000000 s): value not finite (position 0 0 0, "
                 "orientation x y z w 0 0 0 1, linear velocity x y 0.5 -0.01, angular velocity "
                 "z inf)");
  }
  m = odometry(1.0, 0, 0, 0);
  m.pose.pose.orientation.w = 0.0;
  EXPECT_THROW(wheelFromOdometry(m, 1.0, "b"), MessageDecodeError);

  // A TFMessage whose count claims more transforms than its bytes hold.
  tf2_msgs::TFMessage tf;
  tf.transforms.resize(1);
  std::vector<std::uint8_t> tf_bytes = serialize(tf);
  tf_bytes[3] = 0x10;  // 268435457 transforms
  try {
    deserializeTfMessage(tf_bytes.data(), static_cast<std::uint32_t>(tf_bytes.size()), "t");
    FAIL() << "expected MessageDecodeError";
  } catch (const MessageDecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("t: corrupt message: 268435457 transforms need at least"),
              std::string::npos)
        << e.what();
  }
}

TEST(RosOdometry, StaticTransformsComposeEitherWay) {
  std::vector<geometry_msgs::TransformStamped> tfs(3);
  tfs[0].header.frame_id = "/base_link";  // tf1-style leading slash
  tfs[0].child_frame_id = "camera_link";
  tfs[0].transform.translation.x = 0.1;
  tfs[0].transform.translation.z = 0.2;
  tfs[0].transform.rotation.w = 1.0;
  tfs[1].header.frame_id = "camera_link";
  tfs[1].child_frame_id = "imu";
  tfs[1].transform.rotation.z = std::sin(M_PI / 4);  // 90 deg about z
  tfs[1].transform.rotation.w = std::cos(M_PI / 4);
  tfs[2].header.frame_id = "map";
  tfs[2].child_frame_id = "elsewhere";
  tfs[2].transform.rotation.w = 1.0;
  // The pose of base_link in the IMU frame: the inverse of the chain base_link -> imu.
  const auto T = lookupStaticTransform(tfs, "imu", "base_link", "l");
  ASSERT_TRUE(T.has_value());
  Eigen::Isometry3d T_base_imu = Eigen::Isometry3d::Identity();
  T_base_imu.translation() = Eigen::Vector3d(0.1, 0.0, 0.2);
  T_base_imu.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  EXPECT_TRUE(T->isApprox(T_base_imu.inverse(), 1e-12)) << T->matrix();
  // Its translation in numbers: the base is 0.2 m below the IMU, 0.1 m behind it (IMU y).
  EXPECT_NEAR(T->translation().x(), 0.0, 1e-12);
  EXPECT_NEAR(T->translation().y(), 0.1, 1e-12);
  EXPECT_NEAR(T->translation().z(), -0.2, 1e-12);
  EXPECT_TRUE(
      lookupStaticTransform(tfs, "imu", "imu", "l")->isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(lookupStaticTransform(tfs, "imu", "elsewhere", "l").has_value());
  tfs[1].transform.rotation.w = std::nan("");
  EXPECT_THROW(lookupStaticTransform(tfs, "imu", "base_link", "l"), MessageDecodeError);
}

TEST(BagOdometryConversion, ReadingsDeliveredAndBadOnesNamed) {
  const std::string dir = test::makeTempDir("bag_odometry");
  const std::string path = writeBag(dir + "/w.bag", 10, true);
  BagConverter conv(path, ConvertOptions(), BagInputOptions(), smallCamera());
  EXPECT_EQ(conv.layout().odometry, "/odom");
  test::RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(sink.wheels.size(), 50u);  // 51 readings, one not finite
  EXPECT_EQ(r.odometry_messages, 50u);
  EXPECT_EQ(r.unreadable, 1u);
  EXPECT_NE(r.text().find(path + " /odom message "), std::string::npos) << r.text();
  EXPECT_NE(r.text().find("(stamp 50.200000 s): value not finite (position nan 0.02 0"),
            std::string::npos)
      << r.text();
  EXPECT_NE(r.text().find("wheel odometry: /odom (nav_msgs/Odometry, 51 messages)"),
            std::string::npos)
      << r.text();
  for (const WheelOdometrySample& w : sink.wheels) {
    const int i = static_cast<int>(std::lround((w.t - 50.0) / 0.02));
    ASSERT_NE(i, 10);
    EXPECT_NEAR(w.t, 50.0 + 0.02 * i, 1e-6);  // ROS time: nanoseconds
    EXPECT_DOUBLE_EQ(w.x_m, 0.01 * i);
    EXPECT_DOUBLE_EQ(w.y_m, 0.002 * i);
    EXPECT_NEAR(w.yaw_rad, std::remainder(0.03 * i - 1.0 + 2.5, 2 * M_PI), 1e-14);
    EXPECT_TRUE(w.has_velocities);
    EXPECT_DOUBLE_EQ(w.v_forward_m_s, 0.5);
    EXPECT_DOUBLE_EQ(w.yaw_rate_rad_s, 1.5);
  }
  // The wheel frame (base_link) in the body frame (camera_imu_frame, the IMU's frame_id).
  ASSERT_TRUE(conv.T_body_wheel().has_value());
  EXPECT_NEAR(conv.T_body_wheel()->translation().y(), 0.1, 1e-12);
  EXPECT_NEAR(conv.T_body_wheel()->translation().z(), -0.2, 1e-12);
  bool line = false;
  for (const std::string& c : conv.calibration())
    line |=
        c.rfind(
            "wheel frame in the body frame (T_body_wheel, 'base_link' in "
            "'camera_imu_frame'): translation (",
            0) == 0 &&
        c.find("0.0000, 0.1000, -0.2000) m, rotation 90.000 deg (/tf_static)") != std::string::npos;
  EXPECT_TRUE(line) << ::testing::PrintToString(conv.calibration());

  // --odom-topic none: no readings, no wheel extrinsic.
  BagInputOptions none;
  none.topics.odometry = "none";
  BagConverter off(path, ConvertOptions(), none, smallCamera());
  test::RecordingSink quiet;
  EXPECT_TRUE(off.run(quiet).ok());
  EXPECT_TRUE(quiet.wheels.empty());
  EXPECT_EQ(quiet.frames.size(), 11u);
  EXPECT_FALSE(off.T_body_wheel().has_value());
}

TEST(BagOdometryConversion, WithoutTfStaticTheConfigurationsExtrinsicStays) {
  const std::string dir = test::makeTempDir("bag_odometry_notf");
  const std::string path = writeBag(dir + "/w.bag", -1, false);
  BagConverter conv(path, ConvertOptions(), BagInputOptions(), smallCamera());
  EXPECT_FALSE(conv.T_body_wheel().has_value());
  bool line = false;
  for (const std::string& c : conv.calibration())
    line |= c ==
            "wheel frame 'base_link' in 'camera_imu_frame': no /tf_static in the bag; the "
            "configuration's [wheel] R_body_wheel / t_body_wheel_m are used";
  EXPECT_TRUE(line) << ::testing::PrintToString(conv.calibration());
  test::RecordingSink sink;
  EXPECT_TRUE(conv.run(sink).ok());
  EXPECT_EQ(sink.wheels.size(), 51u);
}

TEST(BagOdometryConversion, TruncatedMessagesAndStampsGoingBackAreSkipped) {
  const std::string dir = test::makeTempDir("bag_odometry_bad");
  const std::string path = dir + "/bad.bag", other = dir + "/other.bag";
  sensor_msgs::Image depth;
  depth.width = 32;
  depth.height = 24;
  depth.encoding = "16UC1";
  depth.step = 64;
  depth.data.assign(64 * 24, 3);
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    // Odometry bag times 10.05 .. 10.45 after each depth image; header stamps 10.0, 10.1,
    // (truncated), 10.05 (back), 10.4.
    const double stamps[] = {10.0, 10.1, 10.2, 10.05, 10.4};
    for (int k = 0; k < 5; ++k) {
      const ros::Time t(10.0 + 0.1 * k);
      depth.header.stamp = t;
      bag.write("/camera/aligned_depth_to_color/image_raw", t, depth);
      const nav_msgs::Odometry m = odometry(stamps[k], 0.1 * k, 0, 0);
      if (k == 2) {
        RawOdometry<0> cut{serialize(m)};
        cut.bytes.resize(100);
        bag.write("/odom", t + ros::Duration(0.05), cut);
      } else {
        bag.write("/odom", t + ros::Duration(0.05), m);
      }
    }
  }
  BagConverter conv(path, ConvertOptions(), BagInputOptions(), smallCamera());
  test::RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(sink.wheels.size(), 3u);
  EXPECT_DOUBLE_EQ(sink.wheels[0].x_m, 0.0);
  EXPECT_DOUBLE_EQ(sink.wheels[1].x_m, 0.1);
  EXPECT_DOUBLE_EQ(sink.wheels[2].x_m, 0.4);
  EXPECT_EQ(r.unreadable, 2u);
  // Bag order: depth and odometry alternate, so /odom's messages are 1, 3, 5, 7, 9 of the stream.
  const std::string text = r.text();
  EXPECT_NE(
      text.find(path + " /odom message 5: corrupt message: pose (PoseWithCovariance) needs 344 "
                       "bytes at offset 33, the message has 67 left (of 100)"),
      std::string::npos)
      << text;
  EXPECT_NE(text.find(path + " /odom message 7 (stamp 10.050000 s): odometry stamp not after the "
                             "previous reading's (10.100000 s); skipped"),
            std::string::npos)
      << text;

  // Another message definition under the name nav_msgs/Odometry: refused before converting.
  {
    rosbag::Bag bag(other, rosbag::bagmode::Write);
    depth.header.stamp = ros::Time(10.0);
    bag.write("/camera/aligned_depth_to_color/image_raw", ros::Time(10.0), depth);
    bag.write("/odom", ros::Time(10.0), RawOdometry<1>{serialize(odometry(10.0, 0, 0, 0))});
  }
  try {
    BagConverter refused(other, ConvertOptions(), BagInputOptions(), smallCamera());
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    EXPECT_NE(std::string(e.what()).find(other + ": odometry topic '/odom' has message definition "
                                                 "md5sum 0123456789abcdef0123456789abcdef"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::bag
