// Calibration carried by ROS messages: sensor_msgs/CameraInfo -> PinholeCamera and
// geometry_msgs/Transform -> rigid transform.
#pragma once

#include <geometry_msgs/Transform.h>
#include <sensor_msgs/CameraInfo.h>

#include <Eigen/Geometry>
#include <string>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/common/camera.h"

namespace rgbdi::bag {

class CalibrationError : public BagError {
 public:
  using BagError::BagError;
};

/// Intrinsics from K and the distortion D. Radial-tangential models ("plumb_bob", RealSense's
/// "Brown Conrady", "rational_polynomial" with k4..k6 = 0) keep k1 k2 p1 p2 k3; any model whose
/// coefficients are all zero is distortion-free. Throws CalibrationError naming `label` when K
/// is not a calibrated pinhole matrix or the distortion cannot be represented.
PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info, const std::string& label);

/// The transform as T (rotation normalised); throws CalibrationError for a zero quaternion or
/// non-finite values.
Eigen::Isometry3d isometryFromTransform(const geometry_msgs::Transform& tf,
                                        const std::string& label);

/// "translation (x, y, z) m, rotation A deg" (4 and 3 decimals), for reports.
std::string describePose(const Eigen::Isometry3d& T);

}  // namespace rgbdi::bag
