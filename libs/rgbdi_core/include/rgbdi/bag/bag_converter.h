// Converts a ROS1 bag into a stream of RGB-D frames, IMU samples and ground-truth poses
// (ConversionSink), streaming with bounded memory.
//
// * Layout: see bag_layout.h (dataset / RealSense SDK recording / user topics).
// * Stamps: header stamps (the bag time only when a header stamp is zero).
// * Colour and depth are paired by stamp (RgbdPairer); depth without a colour partner becomes a
//   depth-only frame unless ConvertOptions::require_colour; colour without depth is dropped.
// * Calibration, in order of precedence: the bag's camera_info (intrinsics), RealSense "Depth
//   Units" option (depth unit), RealSense tf (depth-to-colour and, with IMU streams,
//   colour-to-IMU extrinsics); otherwise FallbackCalibration (from --config / --camera-yaml /
//   built-in defaults) and ConvertOptions::integer_depth_unit_m.
// * Wheel odometry (nav_msgs/Odometry, see ros_odometry.h) becomes WheelOdometrySamples; its
//   extrinsic T_body_wheel comes from /tf_static when the bag has it (T_body_wheel()).
// * Damage (see BagReader) ends the stream: run() returns with report.error set, after
//   delivering everything read before the damage. Unreadable single messages are skipped and
//   reported.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include "rgbdi/bag/bag_layout.h"
#include "rgbdi/bag/conversion_report.h"
#include "rgbdi/bag/conversion_sink.h"
#include "rgbdi/bag/convert_options.h"
#include "rgbdi/common/camera.h"

namespace rgbdi::bag {

/// Calibration used for what the input does not carry.
struct FallbackCalibration {
  PinholeCamera color;       ///< colour intrinsics (also depth's when depth is aligned)
  std::string color_source;  ///< where they come from, for the report
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();  ///< colour optical frame in body
  std::string extrinsic_source;
  /// True when the user gave them (--config / --camera-yaml), false for built-in defaults.
  bool intrinsics_from_user = false, extrinsic_from_user = false;
  /// share/config.ini's [camera] and [extrinsic] defaults.
  static FallbackCalibration defaults();
};

struct BagInputOptions {
  TopicOverrides topics;
  std::optional<bool> depth_aligned;  ///< default: the layout's
  /// run() reads the IMU and odometry topics only (no images, no ground truth): the motion
  /// streams, for checks such as rawlog-convert --info's wheel checks.
  bool motion_only = false;
};

class BagConverter {
 public:
  /// Opens the bag, resolves the layout and reads the calibration messages. Throws BagError
  /// (unreadable file, BagLayoutError, CalibrationError) naming the file.
  BagConverter(const std::string& path, const ConvertOptions& options, const BagInputOptions& input,
               const FallbackCalibration& fallback);
  ~BagConverter();
  BagConverter(const BagConverter&) = delete;
  BagConverter& operator=(const BagConverter&) = delete;

  const BagLayout& layout() const;
  /// Colour camera optical frame in the body frame for the written observations' sensorPose.
  const Eigen::Isometry3d& T_body_cam() const;
  const PinholeCamera& colorCamera() const;
  const PinholeCamera& depthCamera() const;
  double depthUnit() const;
  /// Pose of the depth optical frame in the colour optical frame (identity when aligned).
  const Eigen::Isometry3d& T_color_depth() const;
  /// The wheel frame (the odometry's child_frame_id) in the body frame (the IMU's frame_id) from
  /// the bag's /tf_static; nullopt without odometry or without such a transform (calibration()
  /// says which).
  const std::optional<Eigen::Isometry3d>& T_body_wheel() const;
  /// One line per calibration item and where it comes from (also in the run's report).
  const std::vector<std::string>& calibration() const;
  /// The bag being read (topics, times, recovery state).
  const BagReader& reader() const;

  /// Streams the bag into `sink` (once). `progress` gets the fraction of the input consumed;
  /// when *stop becomes true, reading stops and what is buffered is delivered.
  ConversionReport run(ConversionSink& sink, const ProgressCallback& progress = {},
                       const std::atomic<bool>* stop = nullptr);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::bag
