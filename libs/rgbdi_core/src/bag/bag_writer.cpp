#include "rgbdi/bag/bag_writer.h"

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>

namespace rgbdi::bag {

namespace {

/// One message into the bag; a rosbag failure becomes a BagError naming `where` and `what`.
template <class Message>
void writeMessage(rosbag::Bag& bag, const std::string& topic, const ros::Time& stamp,
                  const Message& m, const std::string& where, const char* what) {
  try {
    bag.write(topic, stamp, m);
  } catch (const rosbag::BagException& e) {
    throw BagError(where + ": cannot write " + what + ": " + e.what());
  }
}

}  // namespace

struct BagWriter::Impl {
  rosbag::Bag bag;
  // Reused message buffers: a frame is ~1.5 MB, so avoid reallocating per frame.
  sensor_msgs::Image color, depth;
  std::uint32_t seq_color = 0, seq_imu = 0, seq_pose = 0, seq_odom = 0;
};

std::string toString(Compression c) {
  switch (c) {
    case Compression::None:
      return "none";
    case Compression::Bz2:
      return "bz2";
    case Compression::Lz4:
      return "lz4";
  }
  return "none";
}

Compression parseCompression(const std::string& name) {
  if (name == "none") return Compression::None;
  if (name == "bz2") return Compression::Bz2;
  if (name == "lz4") return Compression::Lz4;
  throw std::invalid_argument("unknown bag compression '" + name + "' (valid: none, bz2, lz4)");
}

namespace {

ros::Time rosTime(double t, const std::string& what) {
  if (!(t > 0.0) || !std::isfinite(t) || t > 4294967295.0)
    throw BagError(what + ": stamp " + std::to_string(t) +
                   " s cannot be a ROS time (must be in (0, 2^32) s)");
  return ros::Time(t);
}

}  // namespace

BagWriter::BagWriter(const std::string& path, Compression compression, const BagTopics& topics)
    : impl_(std::make_unique<Impl>()),
      path_(path),
      tmp_path_(path + ".tmp." + std::to_string(::getpid())),
      topics_(topics) {
  try {
    impl_->bag.open(tmp_path_, rosbag::bagmode::Write);
    impl_->bag.setCompression(compression == Compression::Bz2 ? rosbag::compression::BZ2
                              : compression == Compression::Lz4
                                  ? rosbag::compression::LZ4
                                  : rosbag::compression::Uncompressed);
  } catch (const rosbag::BagException& e) {
    throw BagError(path + ": cannot create bag (temporary " + tmp_path_ + "): " + e.what());
  }
}

BagWriter::~BagWriter() {
  if (impl_) {
    try {
      impl_->bag.close();
    } catch (...) {
      // Destruction after an error: the partial file is removed below anyway.
    }
    impl_.reset();
    std::remove(tmp_path_.c_str());
  }
}

void BagWriter::writeImu(const ImuSample& imu) {
  if (!impl_) throw BagError(path_ + ": write after close()");
  sensor_msgs::Imu m;
  m.header.seq = impl_->seq_imu++;
  m.header.stamp = rosTime(imu.t, path_ + " IMU sample");
  m.header.frame_id = topics_.imu_frame_id;
  // ROS convention: orientation_covariance[0] = -1 means "no orientation estimate".
  m.orientation.w = 1.0;
  m.orientation_covariance[0] = -1.0;
  m.angular_velocity.x = imu.gyr.x();
  m.angular_velocity.y = imu.gyr.y();
  m.angular_velocity.z = imu.gyr.z();
  m.linear_acceleration.x = imu.acc.x();
  m.linear_acceleration.y = imu.acc.y();
  m.linear_acceleration.z = imu.acc.z();
  writeMessage(impl_->bag, topics_.imu, m.header.stamp, m, path_, "IMU message");
  ++messages_;
}

void BagWriter::writeRgbd(const RgbdFrame& frame) {
  if (!impl_) throw BagError(path_ + ": write after close()");
  const std::string what = path_ + " frame " + std::to_string(frame.index);
  if (frame.rgb.type() != CV_8UC3) throw BagError(what + ": colour image must be CV_8UC3 (R,G,B)");
  if (frame.depth.type() != CV_16UC1) throw BagError(what + ": depth image must be CV_16UC1");
  if (!frame.depth_aligned_to_color || frame.depth.size() != frame.rgb.size())
    throw BagError(what + ": depth must be aligned pixel-for-pixel to the colour image");
  const ros::Time stamp = rosTime(frame.t, what);

  sensor_msgs::Image& c = impl_->color;
  c.header.seq = impl_->seq_color;
  c.header.stamp = stamp;
  c.header.frame_id = topics_.camera_frame_id;
  c.height = static_cast<std::uint32_t>(frame.rgb.rows);
  c.width = static_cast<std::uint32_t>(frame.rgb.cols);
  c.encoding = "rgb8";
  c.is_bigendian = 0;
  c.step = c.width * 3;
  c.data.resize(static_cast<size_t>(c.step) * c.height);
  for (int r = 0; r < frame.rgb.rows; ++r)
    std::memcpy(&c.data[static_cast<size_t>(r) * c.step], frame.rgb.ptr(r), c.step);

  sensor_msgs::Image& d = impl_->depth;
  d.header = c.header;
  d.height = c.height;
  d.width = c.width;
  d.encoding = "16UC1";
  d.is_bigendian = 0;
  d.step = d.width * 2;
  d.data.resize(static_cast<size_t>(d.step) * d.height);
  // 16UC1 in the dataset is millimetres; convert other units (rounding, saturating).
  const double scale = frame.depth_unit_m / 1e-3;
  const bool is_mm = std::abs(scale - 1.0) < 1e-12;
  for (int r = 0; r < frame.depth.rows; ++r) {
    const std::uint16_t* src = frame.depth.ptr<std::uint16_t>(r);
    std::uint8_t* dst = &d.data[static_cast<size_t>(r) * d.step];
    for (int x = 0; x < frame.depth.cols; ++x) {
      std::uint16_t v = src[x];
      if (!is_mm) v = static_cast<std::uint16_t>(std::min(65535.0, std::round(v * scale)));
      dst[2 * x] = static_cast<std::uint8_t>(v & 0xff);  // little endian
      dst[2 * x + 1] = static_cast<std::uint8_t>(v >> 8);
    }
  }
  writeMessage(impl_->bag, topics_.color, stamp, c, what, "image messages");
  writeMessage(impl_->bag, topics_.depth, stamp, d, what, "image messages");
  ++impl_->seq_color;
  messages_ += 2;
}

void BagWriter::writePose(double t, const Eigen::Isometry3d& T_world_body) {
  if (!impl_) throw BagError(path_ + ": write after close()");
  geometry_msgs::PoseStamped m;
  m.header.seq = impl_->seq_pose++;
  m.header.stamp = rosTime(t, path_ + " pose");
  m.header.frame_id = topics_.world_frame_id;
  const Eigen::Quaterniond q(T_world_body.rotation());
  m.pose.position.x = T_world_body.translation().x();
  m.pose.position.y = T_world_body.translation().y();
  m.pose.position.z = T_world_body.translation().z();
  m.pose.orientation.x = q.x();
  m.pose.orientation.y = q.y();
  m.pose.orientation.z = q.z();
  m.pose.orientation.w = q.w();
  writeMessage(impl_->bag, topics_.pose, m.header.stamp, m, path_, "pose message");
  ++messages_;
}

void BagWriter::writeOdometry(const WheelOdometrySample& w) {
  if (!impl_) throw BagError(path_ + ": write after close()");
  nav_msgs::Odometry m;
  m.header.seq = impl_->seq_odom++;
  m.header.stamp = rosTime(w.t, path_ + " odometry");
  m.header.frame_id = topics_.odom_frame_id;
  m.child_frame_id = topics_.wheel_frame_id;
  m.pose.pose.position.x = w.x_m;
  m.pose.pose.position.y = w.y_m;
  m.pose.pose.orientation.z = std::sin(0.5 * w.yaw_rad);
  m.pose.pose.orientation.w = std::cos(0.5 * w.yaw_rad);
  if (w.has_velocities) {
    m.twist.twist.linear.x = w.v_forward_m_s;
    m.twist.twist.linear.y = w.v_lateral_m_s;
    m.twist.twist.angular.z = w.yaw_rate_rad_s;
  }
  writeMessage(impl_->bag, topics_.odometry, m.header.stamp, m, path_, "odometry message");
  ++messages_;
}

void BagWriter::writeStaticTransform(double t, const std::string& parent, const std::string& child,
                                     const Eigen::Isometry3d& T_parent_child) {
  if (!impl_) throw BagError(path_ + ": write after close()");
  geometry_msgs::TransformStamped tf;
  tf.header.stamp = rosTime(t, path_ + " static transform");
  tf.header.frame_id = parent;
  tf.child_frame_id = child;
  const Eigen::Quaterniond q(T_parent_child.rotation());
  tf.transform.translation.x = T_parent_child.translation().x();
  tf.transform.translation.y = T_parent_child.translation().y();
  tf.transform.translation.z = T_parent_child.translation().z();
  tf.transform.rotation.x = q.x();
  tf.transform.rotation.y = q.y();
  tf.transform.rotation.z = q.z();
  tf.transform.rotation.w = q.w();
  tf2_msgs::TFMessage m;
  m.transforms.push_back(tf);
  writeMessage(impl_->bag, topics_.tf_static, tf.header.stamp, m, path_, "static transform");
  ++messages_;
}

void BagWriter::close() {
  if (!impl_) return;
  try {
    impl_->bag.close();
  } catch (const rosbag::BagException& e) {
    impl_.reset();
    std::remove(tmp_path_.c_str());
    throw BagError(path_ + ": cannot finish bag: " + e.what());
  }
  impl_.reset();
  std::error_code ec;
  std::filesystem::rename(tmp_path_, path_, ec);
  if (ec) {
    std::remove(tmp_path_.c_str());
    throw BagError(path_ + ": cannot rename " + tmp_path_ + ": " + ec.message());
  }
}

}  // namespace rgbdi::bag
