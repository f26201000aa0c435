// resolveBagLayout on topic lists: the dataset layout, RealSense SDK recordings, realsense-ros
// topics, user overrides ("none" included) and the errors that list the bag's topics.
#include <gtest/gtest.h>

#include "rgbdi/bag/bag_layout.h"

namespace rgbdi::bag {
namespace {

std::vector<BagTopic> datasetTopics() {
  return {{"/camera/aligned_depth_to_color/image_raw", "sensor_msgs/Image", 300},
          {"/camera/color/image_raw", "sensor_msgs/Image", 300},
          {"/camera/imu", "sensor_msgs/Imu", 2000},
          {"/rosout", "rosgraph_msgs/Log", 5},
          {"/vrpn_client_node/Jackal/pose", "geometry_msgs/PoseStamped", 1000}};
}

TEST(BagLayout, PublishedDatasetByDefault) {
  const BagLayout l = resolveBagLayout(datasetTopics(), {}, std::nullopt, "d.bag");
  EXPECT_EQ(l.kind, BagLayoutKind::Dataset);
  EXPECT_EQ(l.color, "/camera/color/image_raw");
  EXPECT_EQ(l.depth, "/camera/aligned_depth_to_color/image_raw");
  EXPECT_EQ(l.imu, "/camera/imu");
  EXPECT_EQ(l.groundtruth, "/vrpn_client_node/Jackal/pose");
  EXPECT_TRUE(l.depth_aligned);
  EXPECT_FALSE(l.color_compressed);
  EXPECT_TRUE(l.color_info.empty());
  EXPECT_TRUE(l.notes.empty());
  const std::vector<std::string> streamed = l.streamedTopics();
  EXPECT_EQ(streamed.size(), 4u);
}

TEST(BagLayout, RealSenseRosWrapperTopicsAndCompressedImages) {
  const std::vector<BagTopic> t = {
      {"/camera/accel/sample", "sensor_msgs/Imu", 250},
      {"/camera/aligned_depth_to_color/camera_info", "sensor_msgs/CameraInfo", 30},
      {"/camera/aligned_depth_to_color/image_raw/compressedDepth", "sensor_msgs/CompressedImage",
       30},
      {"/camera/color/camera_info", "sensor_msgs/CameraInfo", 30},
      {"/camera/color/image_raw/compressed", "sensor_msgs/CompressedImage", 30},
      {"/camera/gyro/sample", "sensor_msgs/Imu", 400},
      {"/mocap/pose", "geometry_msgs/PoseStamped", 100},
      {"/other/pose", "geometry_msgs/PoseStamped", 100}};
  const BagLayout l = resolveBagLayout(t, {}, std::nullopt, "r.bag");
  EXPECT_EQ(l.color, "/camera/color/image_raw/compressed");
  EXPECT_TRUE(l.color_compressed);
  EXPECT_EQ(l.depth, "/camera/aligned_depth_to_color/image_raw/compressedDepth");
  EXPECT_TRUE(l.depth_compressed);
  EXPECT_EQ(l.color_info, "/camera/color/camera_info");
  EXPECT_EQ(l.depth_info, "/camera/aligned_depth_to_color/camera_info");
  EXPECT_TRUE(l.imu.empty());
  EXPECT_EQ(l.accel, "/camera/accel/sample");
  EXPECT_EQ(l.gyro, "/camera/gyro/sample");
  EXPECT_EQ(l.groundtruth, "/mocap/pose");  // first PoseStamped; the choice is noted
  ASSERT_EQ(l.notes.size(), 1u);
  EXPECT_NE(l.notes[0].find("several geometry_msgs/PoseStamped topics"), std::string::npos);
}

TEST(BagLayout, RealSenseSdkRecordingWithImuStreams) {
  const std::vector<BagTopic> t = {
      {"/device_0/sensor_0/Depth_0/image/data", "sensor_msgs/Image", 30},
      {"/device_0/sensor_0/Depth_0/info/camera_info", "sensor_msgs/CameraInfo", 1},
      {"/device_0/sensor_0/Depth_0/tf/0", "geometry_msgs/Transform", 1},
      {"/device_0/sensor_0/Infrared_1/image/data", "sensor_msgs/Image", 30},
      {"/device_0/sensor_0/option/Depth Units/value", "std_msgs/Float32", 1},
      {"/device_0/sensor_1/Color_0/image/data", "sensor_msgs/Image", 30},
      {"/device_0/sensor_1/Color_0/info/camera_info", "sensor_msgs/CameraInfo", 1},
      {"/device_0/sensor_1/Color_0/tf/0", "geometry_msgs/Transform", 1},
      {"/device_0/sensor_2/Accel_0/imu/data", "sensor_msgs/Imu", 63},
      {"/device_0/sensor_2/Accel_0/tf/0", "geometry_msgs/Transform", 1},
      {"/device_0/sensor_2/Gyro_0/imu/data", "sensor_msgs/Imu", 200},
      {"/device_0/sensor_2/Gyro_0/tf/0", "geometry_msgs/Transform", 1}};
  const BagLayout l = resolveBagLayout(t, {}, std::nullopt, "rs.bag");
  EXPECT_EQ(l.kind, BagLayoutKind::RealSense);
  EXPECT_EQ(l.accel, "/device_0/sensor_2/Accel_0/imu/data");
  EXPECT_EQ(l.gyro, "/device_0/sensor_2/Gyro_0/imu/data");
  EXPECT_EQ(l.imu_tf, "/device_0/sensor_2/Accel_0/tf/0");
  EXPECT_EQ(l.depth_units, "/device_0/sensor_0/option/Depth Units/value");
  EXPECT_FALSE(l.depth_aligned);
  // The user may declare the recording aligned (e.g. after an SDK-side alignment).
  EXPECT_TRUE(resolveBagLayout(t, {}, true, "rs.bag").depth_aligned);
}

TEST(BagLayout, OverridesAndNone) {
  std::vector<BagTopic> t = datasetTopics();
  t.push_back({"/cam/rgb", "sensor_msgs/Image", 300});
  TopicOverrides o;
  o.color = "/cam/rgb";
  o.imu = "none";
  o.groundtruth = "none";
  const BagLayout l = resolveBagLayout(t, o, std::nullopt, "d.bag");
  EXPECT_EQ(l.kind, BagLayoutKind::Custom);
  EXPECT_EQ(l.color, "/cam/rgb");
  EXPECT_TRUE(l.imu.empty());
  EXPECT_TRUE(l.groundtruth.empty());
  EXPECT_EQ(l.streamedTopics().size(), 2u);

  TopicOverrides half;
  half.accel = "/camera/imu";
  EXPECT_THROW(resolveBagLayout(t, half, std::nullopt, "d.bag"), BagLayoutError);
}

TEST(BagLayout, ErrorsListTheTopicsThatExist) {
  const std::vector<BagTopic> t = {{"/scan", "sensor_msgs/LaserScan", 100},
                                   {"/odom", "nav_msgs/Odometry", 50}};
  try {
    resolveBagLayout(t, {}, std::nullopt, "x.bag");
    FAIL() << "expected BagLayoutError";
  } catch (const BagLayoutError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("x.bag: no colour or depth image topic found"), std::string::npos) << w;
    EXPECT_NE(w.find("/scan"), std::string::npos) << w;
    EXPECT_NE(w.find("sensor_msgs/LaserScan"), std::string::npos) << w;
    EXPECT_NE(w.find("100 messages"), std::string::npos) << w;
    EXPECT_NE(w.find("--color-topic"), std::string::npos) << w;
  }
  TopicOverrides o;
  o.imu = "/scan";
  std::vector<BagTopic> d = datasetTopics();
  d.push_back({"/scan", "sensor_msgs/LaserScan", 100});
  try {
    resolveBagLayout(d, o, std::nullopt, "x.bag");
    FAIL();
  } catch (const BagLayoutError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "IMU topic '/scan' has type sensor_msgs/LaserScan, expected sensor_msgs/Imu"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::bag
