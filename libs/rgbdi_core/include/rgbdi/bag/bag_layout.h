// Which topics of a ROS1 bag hold what: the published VINS-RGBD dataset layout (SPEC section 6),
// the RealSense SDK recording layout (realsense-viewer / rs-record: /device_0/sensor_N/<Stream>_K/
// ...), or topics named by the user. Detection looks at topic names and message types only.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_reader.h"

namespace rgbdi::bag {

class BagLayoutError : public BagError {
 public:
  using BagError::BagError;
};

enum class BagLayoutKind { Dataset, RealSense, Custom };
std::string toString(BagLayoutKind k);

/// Topic names given by the user; "" = automatic, "none" = do not use that stream.
struct TopicOverrides {
  std::string color, depth, imu, accel, gyro, groundtruth, color_info, depth_info;
  std::string odometry;  ///< nav_msgs/Odometry (--odom-topic)
};

struct BagLayout {
  BagLayoutKind kind = BagLayoutKind::Dataset;
  std::string color, depth;  ///< sensor_msgs/Image or CompressedImage ("" = absent)
  bool color_compressed = false, depth_compressed = false;
  std::string imu;          ///< sensor_msgs/Imu with accelerometer and gyro
  std::string accel, gyro;  ///< separate sensor_msgs/Imu streams, merged on gyro stamps
  std::string groundtruth;  ///< geometry_msgs/PoseStamped
  /// nav_msgs/Odometry of the wheels: the only topic of that type, or the one named.
  std::string odometry;
  std::string tf_static;  ///< tf2_msgs/TFMessage "/tf_static" (static frames: wheel extrinsic)
  std::string color_info, depth_info;  ///< sensor_msgs/CameraInfo
  std::string depth_units;  ///< std_msgs/Float32, metres per depth unit (RealSense option)
  /// geometry_msgs/Transform of each stream to the recording's reference stream (RealSense).
  std::string color_tf, depth_tf, imu_tf;
  bool depth_aligned = true;       ///< depth registered pixel-for-pixel to colour
  std::vector<std::string> notes;  ///< choices made automatically, for the report

  /// The topics streamed during conversion (images, IMU, ground truth, odometry).
  std::vector<std::string> streamedTopics() const;
};

/// Resolves the layout. `depth_aligned` overrides the layout's default (dataset and custom:
/// aligned; RealSense recordings: not aligned). Throws BagLayoutError, whose message lists the
/// bag's topics, when a named topic does not exist or has the wrong type (or, for odometry, the
/// wrong message definition md5sum), when the bag has neither colour nor depth images, or when it
/// has several nav_msgs/Odometry topics and none is named.
BagLayout resolveBagLayout(const std::vector<BagTopic>& topics, const TopicOverrides& overrides,
                           std::optional<bool> depth_aligned, const std::string& path);

/// One line per topic: name, type, message count (for errors and --info).
std::string describeTopics(const std::vector<BagTopic>& topics, const std::string& indent = "  ");

}  // namespace rgbdi::bag
