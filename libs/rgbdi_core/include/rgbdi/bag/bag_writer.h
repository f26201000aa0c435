// Writes RGB-D-inertial data as a ROS1 bag in the layout of the VINS-RGBD dataset (SPEC section
// 6): colour on /camera/color/image_raw (sensor_msgs/Image rgb8), depth aligned to colour on
// /camera/aligned_depth_to_color/image_raw (16UC1 millimetres, same stamp as the colour image),
// IMU on /camera/imu (sensor_msgs/Imu, accelerometer and gyro combined, no orientation) and
// ground truth on /vrpn_client_node/<name>/pose (geometry_msgs/PoseStamped). No camera_info,
// like the published bags. Wheel odometry (optional) on /odom (nav_msgs/Odometry, odom ->
// base_link) with the wheel frame's pose in the IMU frame on /tf_static (tf2_msgs/TFMessage). Uses
// Debian's rosbag storage library; no ROS installation needed.
//
// The bag is written under a temporary name and renamed on close(), so an interrupted run
// leaves no truncated bag. Messages must be written in non-decreasing time per topic.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <stdexcept>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::bag {

class BagError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Chunk compression of the bag (the dataset is published bz2-compressed; RealSense tools use lz4).
enum class Compression { None, Bz2, Lz4 };
std::string toString(Compression c);
/// "none", "bz2", "lz4"; throws std::invalid_argument otherwise.
Compression parseCompression(const std::string& name);

struct BagTopics {
  std::string color = "/camera/color/image_raw";
  std::string depth = "/camera/aligned_depth_to_color/image_raw";
  std::string imu = "/camera/imu";
  std::string pose = "/vrpn_client_node/rgbdi/pose";
  std::string camera_frame_id = "camera_color_optical_frame";
  std::string imu_frame_id = "camera_imu_frame";
  std::string world_frame_id = "world";
  std::string odometry = "/odom";
  std::string odom_frame_id = "odom";        ///< the odometry's header.frame_id
  std::string wheel_frame_id = "base_link";  ///< its child_frame_id
  std::string tf_static = "/tf_static";
};

class BagWriter {
 public:
  /// Opens "<path>.tmp.<pid>" for writing; throws BagError naming the path on failure.
  BagWriter(const std::string& path, Compression compression, const BagTopics& topics = {});
  /// Without close() the temporary file is removed.
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  void writeImu(const ImuSample& imu);
  /// Colour (CV_8UC3 R,G,B) and depth (CV_16UC1, converted to millimetres when depth_unit_m is
  /// not 1e-3) with the frame's stamp. Throws BagError for other image types, or when the depth
  /// is not aligned to the colour image.
  void writeRgbd(const RgbdFrame& frame);
  /// Ground-truth pose of the tracked body in the world frame.
  void writePose(double t, const Eigen::Isometry3d& T_world_body);

  /// One wheel-odometry reading as nav_msgs/Odometry: pose (x, y, yaw about z) of the wheel
  /// frame in the odometry frame, twist (v_forward, v_lateral, yaw rate) in the wheel frame;
  /// covariances zero (MRPT gives none). Encoder ticks have no place in the message.
  void writeOdometry(const WheelOdometrySample& reading);
  /// One /tf_static message with the pose of `child` in `parent` (T_parent_child), stamped `t`.
  void writeStaticTransform(double t, const std::string& parent, const std::string& child,
                            const Eigen::Isometry3d& T_parent_child);
  const BagTopics& topics() const { return topics_; }

  /// Finishes the bag (writes its index) and renames it to the final path.
  void close();
  std::size_t messages() const { return messages_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_, tmp_path_;
  BagTopics topics_;
  std::size_t messages_ = 0;
};

}  // namespace rgbdi::bag
