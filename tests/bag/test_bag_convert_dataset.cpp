// BagConverter round trips: bags written by BagWriter (the dataset layout, every compression)
// convert back to exactly what was written; a synthetic RealSense SDK recording with IMU streams
// (merged on the gyro stamps, extrinsics from tf, depth units from the option topic); compressed
// and float-depth images on user-named topics.
#include <geometry_msgs/Transform.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Float32.h>

#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <random>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_writer.h"
#include "testing/fixtures.h"
#include "testing/recording_sink.h"

namespace rgbdi::bag {
namespace {

using test::RecordingSink;

RgbdFrame randomFrame(std::mt19937_64& rng, double t, std::uint64_t index) {
  RgbdFrame f;
  f.t = t;
  f.index = index;
  f.rgb = cv::Mat(24, 32, CV_8UC3);
  f.depth = cv::Mat(24, 32, CV_16UC1);
  cv::randu(f.rgb, 0, 256);
  std::uniform_int_distribution<int> d(0, 8000);
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 32; ++c)
      f.depth.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(d(rng));
  return f;
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

TEST(BagConvertDataset, BagWriterBagsConvertBackExactly) {
  for (Compression comp : {Compression::None, Compression::Bz2, Compression::Lz4}) {
    SCOPED_TRACE(toString(comp));
    const std::string dir = test::makeTempDir("bag_convert");
    const std::string path = dir + "/seq.bag";
    std::mt19937_64 rng(7);
    cv::theRNG().state = 7;
    std::vector<RgbdFrame> frames;
    std::vector<ImuSample> imus;
    {
      BagWriter w(path, comp);
      for (int k = 0; k < 200; ++k) {
        ImuSample s;
        s.t = 1500.0 + 0.005 * k;
        s.acc = Eigen::Vector3d(0.01 * k, -0.2, 9.81);
        s.gyr = Eigen::Vector3d(0.001 * k, 0.02, -0.03);
        w.writeImu(s);
        imus.push_back(s);
        w.writePose(s.t, Eigen::Isometry3d(Eigen::Translation3d(0.01 * k, 2, 3)));
        if (k % 6 == 0) {
          frames.push_back(randomFrame(rng, s.t + 0.0012, frames.size()));
          w.writeRgbd(frames.back());
        }
      }
      w.close();
    }
    const FallbackCalibration cal = smallCamera();
    BagConverter conv(path, ConvertOptions(), BagInputOptions(), cal);
    EXPECT_EQ(conv.layout().kind, BagLayoutKind::Dataset);
    RecordingSink sink;
    const ConversionReport r = conv.run(sink);
    ASSERT_TRUE(r.ok()) << r.error;
    ASSERT_EQ(sink.frames.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const RgbdFrame& a = sink.frames[i];
      EXPECT_NEAR(a.t, frames[i].t, 1e-9);  // ROS stamps have nanosecond resolution
      EXPECT_EQ(cv::countNonZero(a.depth != frames[i].depth), 0) << i;
      cv::Mat diff;
      cv::absdiff(a.rgb, frames[i].rgb, diff);
      EXPECT_EQ(cv::countNonZero(diff.reshape(1)), 0) << i;
      EXPECT_DOUBLE_EQ(a.depth_unit_m, 1e-3);
      EXPECT_TRUE(a.depth_aligned_to_color);
      EXPECT_DOUBLE_EQ(a.cam_color.fx, 30.0);
      EXPECT_DOUBLE_EQ(a.cam_depth.cx, 16.0);
    }
    ASSERT_EQ(sink.imus.size(), imus.size());
    for (std::size_t i = 0; i < imus.size(); ++i) {
      EXPECT_NEAR(sink.imus[i].t, imus[i].t, 1e-9);
      EXPECT_EQ(sink.imus[i].acc, imus[i].acc);
      EXPECT_EQ(sink.imus[i].gyr, imus[i].gyr);
    }
    ASSERT_EQ(sink.poses.size(), 200u);
    EXPECT_DOUBLE_EQ(sink.poses[10].p.x(), 0.1);
    EXPECT_EQ(r.pairing.pairs, frames.size());
    EXPECT_EQ(r.imu_messages, 200u);
    EXPECT_EQ(r.groundtruth_poses, 200u);
    EXPECT_TRUE(conv.T_body_cam().isApprox(cal.T_body_cam));
  }
}

TEST(BagConvertDataset, CalibrationThatDoesNotFitTheImagesStopsTheConversion) {
  const std::string dir = test::makeTempDir("bag_convert");
  std::mt19937_64 rng(1);
  {
    BagWriter w(dir + "/s.bag", Compression::None);
    w.writeRgbd(randomFrame(rng, 10.0, 0));
    w.close();
  }
  BagConverter conv(dir + "/s.bag", ConvertOptions(), BagInputOptions(),
                    FallbackCalibration::defaults());
  RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  EXPECT_FALSE(r.ok());
  EXPECT_NE(
      r.error.find(
          "images are 32x24 but the intrinsics (built-in defaults (share/config.ini [camera])) "
          "are for 640x480"),
      std::string::npos)
      << r.error;
  EXPECT_TRUE(sink.frames.empty());
}

// ------------------------------------------------------------------------------------------
// A RealSense SDK recording written here: Accel at 50 Hz and Gyro at 200 Hz, tf of Accel and
// Color to the depth stream, Depth Units 0.0001, camera_info per stream, depth not aligned.

sensor_msgs::CameraInfo info(double fx, double cx) {
  sensor_msgs::CameraInfo i;
  i.width = 32;
  i.height = 24;
  i.K = {fx, 0, cx, 0, fx, 12, 0, 0, 1};
  i.distortion_model = "Brown Conrady";
  i.D = {0, 0, 0, 0, 0};
  return i;
}

/// A RealSense tf message as the SDK writes it: T_stream_ref (p_stream = R p_ref + t). The SDK's
/// rot2quat yields the negated quaternion (w < 0 for small rotations); `negate` does the same.
geometry_msgs::Transform transform(const Eigen::Isometry3d& T, bool negate = false) {
  geometry_msgs::Transform tf;
  const Eigen::Quaterniond q(T.rotation());
  const double s = negate ? -1.0 : 1.0;
  tf.rotation.x = s * q.x();
  tf.rotation.y = s * q.y();
  tf.rotation.z = s * q.z();
  tf.rotation.w = s * q.w();
  tf.translation.x = T.translation().x();
  tf.translation.y = T.translation().y();
  tf.translation.z = T.translation().z();
  return tf;
}

TEST(BagConvertDataset, RealSenseRecordingWithImuStreams) {
  const std::string dir = test::makeTempDir("bag_convert");
  const std::string path = dir + "/rs.bag";
  // The SDK's tf convention: each stream's tf/0 is T_stream_depth (the depth stream is the
  // reference, its own tf the identity).
  const Eigen::Isometry3d T_color_depth(Eigen::Translation3d(0.015, 0.0, 0.0) *
                                        Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY()));
  const Eigen::Isometry3d T_imu_depth(Eigen::Translation3d(-0.01, 0.005, 0.02) *
                                      Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()));
  const ros::Time t0(1.0e-9);
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::LZ4);
    bag.write("/device_0/sensor_0/Depth_0/info/camera_info", t0, info(20.0, 15.0));
    bag.write("/device_0/sensor_1/Color_0/info/camera_info", t0, info(30.0, 16.0));
    bag.write("/device_0/sensor_0/Depth_0/tf/0", t0, transform(Eigen::Isometry3d::Identity()));
    bag.write("/device_0/sensor_1/Color_0/tf/0", t0, transform(T_color_depth));
    bag.write("/device_0/sensor_2/Accel_0/tf/0", t0, transform(T_imu_depth, true));
    bag.write("/device_0/sensor_2/Gyro_0/tf/0", t0, transform(T_imu_depth, true));
    std_msgs::Float32 units;
    units.data = 0.0001f;
    bag.write("/device_0/sensor_0/option/Depth Units/value", t0, units);
    for (int k = 0; k < 400; ++k) {  // 2 s of gyro at 200 Hz, accelerometer at 50 Hz
      const double t = 100.0 + 0.005 * k;
      const ros::Time bag_t(0.001 + 0.005 * k);  // the SDK's bag time starts at 0
      sensor_msgs::Imu g;
      g.header.stamp = ros::Time(t);
      g.angular_velocity.x = 0.5 * (t - 100.0);
      bag.write("/device_0/sensor_2/Gyro_0/imu/data", bag_t, g);
      if (k % 4 == 0) {
        sensor_msgs::Imu a;
        a.header.stamp = ros::Time(t + 0.001);
        a.linear_acceleration.z = 9.0 + (t + 0.001 - 100.0);  // linear in time: exact interpolation
        bag.write("/device_0/sensor_2/Accel_0/imu/data", bag_t, a);
      }
      if (k % 10 == 0) {
        sensor_msgs::Image d;
        d.header.stamp = ros::Time(t + 0.002);
        d.encoding = "mono16";
        d.width = 32;
        d.height = 24;
        d.step = 64;
        d.data.assign(64 * 24, 0);
        d.data[0] = static_cast<std::uint8_t>(k);
        d.data[1] = 0x27;  // 0x27xx units of 0.1 mm = about 1 m
        bag.write("/device_0/sensor_0/Depth_0/image/data", bag_t, d);
        sensor_msgs::Image c;
        c.header.stamp = ros::Time(t + 0.0025);
        c.encoding = "rgb8";
        c.width = 32;
        c.height = 24;
        c.step = 96;
        c.data.assign(96 * 24, static_cast<std::uint8_t>(k));
        bag.write("/device_0/sensor_1/Color_0/image/data", bag_t, c);
      }
    }
  }
  BagConverter conv(path, ConvertOptions(), BagInputOptions(), FallbackCalibration::defaults());
  EXPECT_EQ(conv.layout().kind, BagLayoutKind::RealSense);
  EXPECT_DOUBLE_EQ(conv.depthUnit(), 0.0001);
  EXPECT_DOUBLE_EQ(conv.depthCamera().fx, 20.0);
  EXPECT_DOUBLE_EQ(conv.colorCamera().fx, 30.0);
  EXPECT_TRUE(conv.T_color_depth().isApprox(T_color_depth, 1e-12));
  // rgbdi's body is the IMU: T_body_cam = T_imu_color = T_imu_depth * T_depth_color.
  EXPECT_TRUE(conv.T_body_cam().isApprox(T_imu_depth * T_color_depth.inverse(), 1e-12));

  RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  ASSERT_TRUE(r.ok()) << r.error;
  // Gyro stamps 100.000 .. 101.995; accelerometer 100.001 .. 101.981: the first gyro sample is
  // before it and the last three after it.
  EXPECT_EQ(r.merge.gyro_before_accel, 1u);
  EXPECT_EQ(r.merge.gyro_after_accel, 3u);
  ASSERT_EQ(sink.imus.size(), 396u);
  for (const ImuSample& s : sink.imus) {
    EXPECT_NEAR(s.acc.z(), 9.0 + (s.t - 100.0), 1e-9);
    EXPECT_NEAR(s.gyr.x(), 0.5 * (s.t - 100.0), 1e-9);
  }
  ASSERT_EQ(sink.frames.size(), 40u);
  EXPECT_EQ(r.pairing.pairs, 40u);
  const RgbdFrame& f = sink.frames[3];
  EXPECT_NEAR(f.t, 100.0 + 0.005 * 30 + 0.0025, 1e-9);  // colour stamp
  EXPECT_EQ(f.depth.at<std::uint16_t>(0, 0), 0x2700 + 30);
  EXPECT_DOUBLE_EQ(f.depth_unit_m, 0.0001);
  EXPECT_FALSE(f.depth_aligned_to_color);
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(5, 5), cv::Vec3b(30, 30, 30));
}

/// A RealSense recording with one image / IMU message per stream and the given tf topics.
void writeRealSenseExtrinsics(const std::string& path,
                              const std::vector<std::pair<std::string, Eigen::Isometry3d>>& tfs) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  const ros::Time t0(1.0);
  for (const auto& [topic, T] : tfs) bag.write(topic, t0, transform(T));
  sensor_msgs::Image img;
  img.header.stamp = t0;
  img.width = 32;
  img.height = 24;
  img.encoding = "mono16";
  img.step = 64;
  img.data.assign(64 * 24, 0);
  bag.write("/device_0/sensor_0/Depth_0/image/data", t0, img);
  img.encoding = "rgb8";
  img.step = 96;
  img.data.assign(96 * 24, 0);
  bag.write("/device_0/sensor_1/Color_0/image/data", t0, img);
  sensor_msgs::Imu m;
  m.header.stamp = t0;
  bag.write("/device_0/sensor_2/Accel_0/imu/data", t0, m);
  bag.write("/device_0/sensor_2/Gyro_0/imu/data", t0, m);
}

TEST(BagConvertDataset, RealSenseExtrinsicsComposeThroughTheirCommonReference) {
  const std::string dir = test::makeTempDir("bag_convert");
  // A reference that is none of the streams: every tf is T_stream_ref.
  const Eigen::Isometry3d T_depth_ref(Eigen::Translation3d(0.05, -0.01, 0.002) *
                                      Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitZ()));
  const Eigen::Isometry3d T_color_ref(Eigen::Translation3d(0.035, 0.001, 0.0) *
                                      Eigen::AngleAxisd(-0.02, Eigen::Vector3d::UnitY()));
  const Eigen::Isometry3d T_imu_ref(Eigen::Translation3d(-0.006, 0.005, 0.012) *
                                    Eigen::AngleAxisd(0.04, Eigen::Vector3d::UnitX()));
  writeRealSenseExtrinsics(dir + "/a.bag", {{"/device_0/sensor_0/Depth_0/tf/0", T_depth_ref},
                                            {"/device_0/sensor_1/Color_0/tf/0", T_color_ref},
                                            {"/device_0/sensor_2/Accel_0/tf/0", T_imu_ref},
                                            {"/device_0/sensor_2/Gyro_0/tf/0", T_imu_ref}});
  BagConverter conv(dir + "/a.bag", ConvertOptions(), BagInputOptions(), smallCamera());
  // A point seen by the depth camera, in the colour camera: through the reference frame.
  const Eigen::Vector3d p_depth(0.3, -0.2, 1.7);
  const Eigen::Vector3d p_ref = T_depth_ref.inverse() * p_depth;
  EXPECT_LT((conv.T_color_depth() * p_depth - T_color_ref * p_ref).norm(), 1e-12);
  EXPECT_LT((conv.T_body_cam() * (T_color_ref * p_ref) - T_imu_ref * p_ref).norm(), 1e-12);
  std::string cal;
  for (const std::string& line : conv.calibration()) cal += line + "\n";
  EXPECT_NE(cal.find("depth camera in the colour camera (T_color_depth): translation"),
            std::string::npos)
      << cal;
  EXPECT_NE(cal.find("colour camera in the IMU (body) frame (T_body_cam)"), std::string::npos)
      << cal;

  // Extrinsics of different groups cannot be combined: identity / the configured extrinsic.
  writeRealSenseExtrinsics(dir + "/b.bag", {{"/device_0/sensor_0/Depth_0/tf/0", T_depth_ref},
                                            {"/device_0/sensor_1/Color_0/tf/1", T_color_ref},
                                            {"/device_0/sensor_2/Accel_0/tf/0", T_imu_ref}});
  BagConverter other(dir + "/b.bag", ConvertOptions(), BagInputOptions(), smallCamera());
  EXPECT_TRUE(other.T_color_depth().isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(other.T_body_cam().isApprox(smallCamera().T_body_cam));
  std::string cal2;
  for (const std::string& line : other.calibration()) cal2 += line + "\n";
  EXPECT_NE(cal2.find("/device_0/sensor_1/Color_0/tf/1 and /device_0/sensor_0/Depth_0/tf/0 "
                      "have different references); identity used"),
            std::string::npos)
      << cal2;
  EXPECT_NE(cal2.find("/device_0/sensor_2/Accel_0/tf/0 and /device_0/sensor_1/Color_0/tf/1 have "
                      "different references)"),
            std::string::npos)
      << cal2;
}

TEST(BagConvertDataset, CompressedAndFloatDepthOnUserTopics) {
  const std::string dir = test::makeTempDir("bag_convert");
  const std::string path = dir + "/c.bag";
  cv::Mat bgr(24, 32, CV_8UC3, cv::Scalar(10, 20, 200));
  std::vector<std::uint8_t> png;
  cv::imencode(".png", bgr, png);
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.setCompression(rosbag::compression::BZ2);
    for (int k = 0; k < 5; ++k) {
      const ros::Time t(50.0 + 0.1 * k);
      sensor_msgs::CompressedImage c;
      c.header.stamp = t;
      c.format = "bgr8; png compressed bgr8";
      c.data = png;
      bag.write("/cam/rgb/compressed", t, c);
      sensor_msgs::Image d;
      d.header.stamp = k == 2 ? ros::Time() : t;  // one zero stamp: the bag time is used
      d.encoding = "32FC1";
      d.width = 32;
      d.height = 24;
      d.step = 128;
      d.data.resize(128 * 24);
      std::vector<float> z(32 * 24, 1.5f + 0.25f * static_cast<float>(k));
      std::memcpy(d.data.data(), z.data(), d.data.size());
      bag.write("/cam/depth", t, d);
      sensor_msgs::Image bad = d;
      bad.encoding = "64FC1";
      if (k == 4) bag.write("/cam/depth", t + ros::Duration(0.5), bad);
    }
  }
  BagInputOptions in;
  in.topics.color = "/cam/rgb/compressed";
  in.topics.depth = "/cam/depth";
  BagConverter conv(path, ConvertOptions(), in, smallCamera());
  EXPECT_EQ(conv.layout().kind, BagLayoutKind::Custom);
  RecordingSink sink;
  const ConversionReport r = conv.run(sink);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(sink.frames.size(), 5u);
  for (int k = 0; k < 5; ++k) {
    const RgbdFrame& f = sink.frames[static_cast<size_t>(k)];
    EXPECT_NEAR(f.t, 50.0 + 0.1 * k, 1e-9);
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(3, 3), cv::Vec3b(200, 20, 10));
    EXPECT_EQ(f.depth.at<std::uint16_t>(3, 3), static_cast<std::uint16_t>(1500 + 250 * k));
  }
  EXPECT_EQ(r.stamps_from_bag_time, 1u);
  EXPECT_EQ(r.unreadable, 1u);
  EXPECT_NE(r.text().find("unsupported depth encoding '64FC1'"), std::string::npos) << r.text();
}

}  // namespace
}  // namespace rgbdi::bag
