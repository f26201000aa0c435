// The wheel extrinsic of a ROS1 bag: T_body_wheel, the wheel frame (the odometry's
// child_frame_id) in rgbdi's body frame (the IMU messages' frame_id), composed along the bag's
// /tf_static (ros_odometry.h lookupStaticTransform). Without /tf_static, without a connection
// between the two frames, or without either frame name, there is none and the configuration's
// [wheel] R_body_wheel / t_body_wheel_m stay; the lines for the report say which.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_layout.h"
#include "rgbdi/bag/bag_reader.h"

namespace rgbdi::bag {

struct BagWheelExtrinsic {
  std::optional<Eigen::Isometry3d> T_body_wheel;
  std::vector<std::string> lines;  ///< for the calibration part of the report
};

/// Reads the extrinsic for `layout.odometry` (nothing without odometry). Leaves `reader`
/// selecting /tf_static: select() again before streaming. Throws CalibrationError
/// (ros_calibration.h) naming the message for an unreadable /tf_static message or a transform with
/// invalid values; damage in the bag ends the reading of /tf_static (noted in the lines).
BagWheelExtrinsic readWheelExtrinsic(BagReader& reader, const BagLayout& layout,
                                     const std::string& path);

}  // namespace rgbdi::bag
