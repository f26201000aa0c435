// TUM RGB-D benchmark folders (rgb.txt, depth.txt, accelerometer.txt, groundtruth.txt and the
// rgb/ and depth/ PNG images) as a conversion source.
//
// * Colour (8-bit PNG) and depth (16-bit PNG, `ConvertOptions::tum_depth_factor` units per metre,
//   5000 in the benchmark; 0 = invalid) are paired by stamp like bag images (RgbdPairer); the
//   depth images are registered to the colour camera, so depth is aligned.
// * Intrinsics: the TUM calibration of the colour camera of freiburg1/2/3 (or ROS' default) by
//   name or detected from the folder name, else the user's --config / --camera-yaml.
// * The TUM Kinect has no gyroscope: accelerometer.txt becomes acceleration-only IMU samples.
// * groundtruth.txt (the colour camera's pose from motion capture) becomes ground-truth poses.
// Lists are read line by line with errors naming the file and line; a missing or unreadable
// image is skipped and reported.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/conversion_report.h"
#include "rgbdi/bag/conversion_sink.h"
#include "rgbdi/bag/convert_options.h"
#include "rgbdi/common/camera.h"

namespace rgbdi::convert {

/// "fr1", "fr2", "fr3" (TUM's colour camera calibration) or "ros" (ROS' default 525/319.5/239.5),
/// all 640x480. Throws std::invalid_argument for other names.
PinholeCamera tumCamera(const std::string& name);
/// "fr1".."fr3" when the folder's name contains freiburg1..3 or fr1..fr3; "" otherwise.
std::string detectTumCamera(const std::string& folder);

struct TumImageEntry {
  double t = 0.0;
  std::string file;  ///< relative to the folder
};

/// Reads rgb.txt / depth.txt ("timestamp filename" per line, '#' comments). Throws IoError naming
/// the file and line.
std::vector<TumImageEntry> readTumImageList(const std::string& path);

class TumRgbdConverter {
 public:
  /// `camera`: "" (from the folder name, else the user's calibration), "fr1", "fr2", "fr3",
  /// "ros", or "config" (the user's --config / --camera-yaml calibration). Reads the lists;
  /// throws IoError (unreadable folder or list) or std::invalid_argument (no intrinsics known).
  TumRgbdConverter(const std::string& folder, const bag::ConvertOptions& options,
                   const std::string& camera, const bag::FallbackCalibration& fallback);

  const PinholeCamera& camera() const { return camera_; }
  /// Colour camera in the body frame: identity (TUM has no IMU frame) unless the user gave one.
  const Eigen::Isometry3d& T_body_cam() const { return T_body_cam_; }
  /// Bytes of the listed image files (for progress).
  std::uint64_t totalBytes() const { return total_bytes_; }

  bag::ConversionReport run(bag::ConversionSink& sink, const bag::ProgressCallback& progress = {},
                            const std::atomic<bool>* stop = nullptr);

 private:
  std::string folder_;
  bag::ConvertOptions options_;
  PinholeCamera camera_;
  Eigen::Isometry3d T_body_cam_ = Eigen::Isometry3d::Identity();
  std::vector<std::string> calibration_;
  std::vector<TumImageEntry> rgb_, depth_;
  std::uint64_t total_bytes_ = 0;
};

}  // namespace rgbdi::convert
