// Writes IMU samples, RGB-D frames, wheel odometry (or any MRPT object) to a rawlog that MRPT tools
// (rawlog-edit, RawLogViewer) and RawlogSource read. The file is written under a temporary name
// and renamed on close(), so an interrupted run never leaves a truncated rawlog behind.
//
// Colour images stored inside the rawlog are stored raw (MRPT 2.5's default
// CImage::DISABLE_JPEG_COMPRESSION is true); with external_images they are lossless PNG files and
// depth is stored
// as MRPT's external range files, both in "<dir>/<stem>_Images/".
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/serialization/CSerializable.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::io {

struct RawlogWriterOptions {
  enum class Layout {
    Observations,   ///< a plain sequence of observations (MRPT's "observations-only" format)
    SensoryFrames,  ///< (empty CActionCollection, CSensoryFrame with one observation) pairs
  };
  Layout layout = Layout::Observations;
  bool gzip = false;             ///< gzip-compress the rawlog
  bool external_images = false;  ///< colour PNG + depth range files in <stem>_Images/
  std::string imu_label = "IMU";
  std::string camera_label = "RGBD";
  std::string wheel_label = "WHEEL_ODOMETRY";  ///< of the CObservationOdometry records
  /// Pose of the colour camera optical frame in the body frame, stored as each frame's sensorPose.
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
};

class RawlogWriter {
 public:
  /// Creates the output, its directory and the image directory if needed; throws IoError on
  /// failure.
  RawlogWriter(const std::string& path, const RawlogWriterOptions& options);
  /// Without close() (e.g. during stack unwinding) the temporary file is removed.
  ~RawlogWriter();
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void write(const ImuSample& imu);
  void write(const RgbdFrame& frame);
  void write(const WheelOdometrySample& wheel);
  /// An observation, wrapped according to the layout.
  void writeObservation(const mrpt::obs::CObservation::Ptr& obs);
  /// Any serializable object as one top-level record, whatever the layout.
  void writeRaw(const mrpt::serialization::CSerializable& obj);

  /// Flushes and renames the temporary file to the final path; throws IoError on failure.
  void close();
  std::size_t records() const { return records_; }
  /// "<dir>/<stem>_Images": where external images go.
  const std::string& imagesDirectory() const { return images_dir_; }

 private:
  struct Stream;
  std::string path_, tmp_path_, images_dir_;
  RawlogWriterOptions options_;
  std::unique_ptr<Stream> stream_;
  std::size_t records_ = 0;
  std::size_t frames_ = 0;
};

}  // namespace rgbdi::io
