// Plain sensor-data and pose structs shared by every pipeline stage.
// Units: seconds, metres, radians, m/s^2, rad/s. Frames are named in the field names:
// T_a_b maps points from frame b into frame a (p_a = T_a_b * p_b).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "rgbdi/common/camera.h"

namespace rgbdi {

/// One IMU sample in the IMU (body) frame.
struct ImuSample {
  double t = 0.0;  ///< [s]
  Eigen::Vector3d acc =
      Eigen::Vector3d::Zero();  ///< specific force [m/s^2] (gravity reaction included)
  Eigen::Vector3d gyr = Eigen::Vector3d::Zero();  ///< angular rate [rad/s]
};

/// One RGB-D frame: colour image and depth image with the calibration needed to use them.
struct RgbdFrame {
  double t = 0.0;  ///< [s] stamp of the colour image (depth has the same stamp or is paired)
  std::uint64_t index = 0;     ///< running index of the frame in its stream
  cv::Mat rgb;                 ///< CV_8UC3 in R,G,B order; may be empty for depth-only frames
  cv::Mat depth;               ///< CV_16UC1 raw depth units; 0 = invalid; may be empty
  double depth_unit_m = 1e-3;  ///< metres per depth unit
  PinholeCamera cam_color;     ///< intrinsics of the colour camera
  PinholeCamera cam_depth;     ///< intrinsics of the depth camera
  /// Pose of the depth camera (optical frame, z forward) in the colour camera optical frame.
  Eigen::Isometry3d T_color_depth = Eigen::Isometry3d::Identity();
  /// True when depth is already registered pixel-for-pixel to the colour image.
  bool depth_aligned_to_color = true;
  /// Optional: pose of the colour camera optical frame in the body frame as stored in the source
  /// (MRPT sensorPose); only used to warn when it disagrees with the configured extrinsic.
  bool has_source_T_body_cam = false;
  Eigen::Isometry3d source_T_body_cam = Eigen::Isometry3d::Identity();
  std::string source_label;  ///< e.g. "sequence.rawlog record 123", for messages
  /// True when `rgb` and `depth` were allocated for this frame alone and nothing writes into
  /// them again (a decoder's new images): a consumer that keeps the frame beyond the call may
  /// share the buffers instead of copying them. False (the default) when a source may reuse
  /// them for a later frame (a grabber's buffers, images wrapping memory the caller owns).
  bool images_exclusive = false;

  bool hasColor() const { return !rgb.empty(); }
  bool hasDepth() const { return !depth.empty(); }
  /// Depth in metres at integer pixel (u, v) of the depth image; 0 when invalid.
  double depthAt(int u, int v) const {
    const std::uint16_t d = depth.at<std::uint16_t>(v, u);
    return d == 0 ? 0.0 : d * depth_unit_m;
  }
};

/// A timestamped rigid pose T_world_frame (quaternion + translation), e.g. one line of a TUM file.
struct StampedPose {
  double t = 0.0;
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();

  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = p;
    return T;
  }
  static StampedPose fromIsometry(double t, const Eigen::Isometry3d& T) {
    StampedPose s;
    s.t = t;
    s.q = Eigen::Quaterniond(T.rotation()).normalized();
    s.p = T.translation();
    return s;
  }
};

using Trajectory = std::vector<StampedPose>;

}  // namespace rgbdi
