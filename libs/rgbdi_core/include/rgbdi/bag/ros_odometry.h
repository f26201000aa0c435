// Wheel odometry and static frames from ROS1 messages: nav_msgs/Odometry -> WheelOdometrySample
// (what rgbdi's rawlog reader takes from a CObservationOdometry) and tf2_msgs/TFMessage
// (/tf_static) -> the transform between two frames. Every length field is checked against the
// bytes of the message before anything is allocated (wire_check.h).
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::bag {

/// A message that cannot be decoded, or whose values cannot be used; what() names `label`.
class MessageDecodeError : public BagError {
 public:
  using BagError::BagError;
};

/// Deserialises one nav_msgs/Odometry. Throws MessageDecodeError naming `label`, the field, its
/// offset and the bytes left when the message is truncated or a length runs past its end.
nav_msgs::Odometry deserializeOdometry(const std::uint8_t* data, std::uint32_t size,
                                       const std::string& label);

/// The planar reading of `msg` stamped `t`: x, y of pose.pose.position and the yaw of its
/// orientation (ZYX: atan2(2 (w z + x y), 1 - 2 (y^2 + z^2)), in (-pi, pi]) as the pose of the
/// child frame in the odometry frame; twist.twist.linear.x / .y and angular.z (in the child
/// frame, as ROS defines it) as the velocities (has_velocities). No encoder ticks. Throws
/// MessageDecodeError naming `label` and the values when one is not finite or the quaternion is
/// zero.
WheelOdometrySample wheelFromOdometry(const nav_msgs::Odometry& msg, double t,
                                      const std::string& label);

/// Deserialises one tf2_msgs/TFMessage into its transforms (same checks as above, the element
/// count included).
std::vector<geometry_msgs::TransformStamped> deserializeTfMessage(const std::uint8_t* data,
                                                                  std::uint32_t size,
                                                                  const std::string& label);

/// T_target_source (the pose of `source` in `target`) composed along the static transforms
/// (each is the pose of child_frame_id in header.frame_id; a chain may run either way through
/// each); nullopt when the two frames are not connected. A leading '/' of a frame name is
/// ignored (tf1 style). Throws MessageDecodeError naming `label` for a transform with non-finite
/// values or a zero quaternion on the path.
std::optional<Eigen::Isometry3d> lookupStaticTransform(
    const std::vector<geometry_msgs::TransformStamped>& transforms, const std::string& target,
    const std::string& source, const std::string& label);

}  // namespace rgbdi::bag
