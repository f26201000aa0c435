#include "rgbdi/bag/wheel_extrinsic.h"

#include <ros/serialization.h>
#include <sensor_msgs/Imu.h>

#include "rgbdi/bag/ros_calibration.h"
#include "rgbdi/bag/ros_odometry.h"

namespace rgbdi::bag {
namespace {

/// The odometry's child_frame_id ("" when its first message is missing or unreadable: the
/// stream reports that message when it reaches it).
std::string wheelFrame(const BagReader& reader, const std::string& topic, const std::string& path) {
  std::vector<std::uint8_t> bytes;
  if (!reader.firstMessage(topic, bytes)) return std::string();
  try {
    return deserializeOdometry(bytes.data(), static_cast<std::uint32_t>(bytes.size()),
                               path + " " + topic)
        .child_frame_id;
  } catch (const MessageDecodeError&) {
    return std::string();
  }
}

/// The IMU's header.frame_id ("" when missing or unreadable, likewise).
std::string imuFrame(const BagReader& reader, const std::string& topic) {
  std::vector<std::uint8_t> bytes;
  if (topic.empty() || !reader.firstMessage(topic, bytes)) return std::string();
  sensor_msgs::Imu msg;
  try {
    ros::serialization::IStream s(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
    ros::serialization::deserialize(s, msg);
  } catch (const ros::Exception&) {
    return std::string();
  }
  return msg.header.frame_id;
}

}  // namespace

BagWheelExtrinsic readWheelExtrinsic(BagReader& reader, const BagLayout& layout,
                                     const std::string& path) {
  BagWheelExtrinsic out;
  if (layout.odometry.empty()) return out;
  const std::string wheel_frame = wheelFrame(reader, layout.odometry, path);
  const std::string body_frame = imuFrame(reader, !layout.imu.empty() ? layout.imu : layout.gyro);
  const std::string keep = "; the configuration's [wheel] R_body_wheel / t_body_wheel_m are used";
  if (wheel_frame.empty() || body_frame.empty()) {
    out.lines.push_back("wheel frame in the body frame: unknown (" +
                        std::string(wheel_frame.empty() ? "the odometry has no child_frame_id"
                                                        : "no IMU frame_id") +
                        ")" + keep);
    return out;
  }
  std::vector<geometry_msgs::TransformStamped> transforms;
  if (!layout.tf_static.empty()) {
    reader.select({layout.tf_static});
    BagMessage m;
    try {
      while (reader.next(m)) {
        const std::string where = path + " " + *m.topic + " message " + std::to_string(m.ordinal);
        try {
          const auto t = deserializeTfMessage(m.data, m.size, where);
          transforms.insert(transforms.end(), t.begin(), t.end());
        } catch (const std::exception& e) {
          throw CalibrationError(e.what());
        }
      }
    } catch (const BagReadError& e) {
      // Damage: the transforms before it are used; the stream reports the damage itself.
      out.lines.push_back(layout.tf_static + " read up to damage: " + e.what());
    }
  }
  const std::string frames = "'" + wheel_frame + "' in '" + body_frame + "'";
  if (transforms.empty()) {
    out.lines.push_back("wheel frame " + frames + ": no /tf_static in the bag" + keep);
    return out;
  }
  try {
    out.T_body_wheel =
        lookupStaticTransform(transforms, body_frame, wheel_frame, path + " " + layout.tf_static);
  } catch (const MessageDecodeError& e) {
    throw CalibrationError(e.what());
  }
  if (out.T_body_wheel)
    out.lines.push_back("wheel frame in the body frame (T_body_wheel, " + frames +
                        "): " + describePose(*out.T_body_wheel) + " (" + layout.tf_static + ")");
  else
    out.lines.push_back("wheel frame " + frames + ": not connected in " + layout.tf_static + keep);
  return out;
}

}  // namespace rgbdi::bag
