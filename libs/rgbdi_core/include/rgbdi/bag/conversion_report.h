// What a dataset conversion (ROS1 bag or TUM RGB-D folder -> rawlog) read, wrote, dropped and
// why; printed by rawlog-convert at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "rgbdi/bag/accel_gyro_merger.h"
#include "rgbdi/bag/rgbd_pairer.h"

namespace rgbdi::bag {

struct ConversionReport {
  std::string input;                     ///< path of the input
  std::string format;                    ///< e.g. "ROS1 bag, RealSense SDK recording layout"
  std::vector<std::string> streams;      ///< which topic / file feeds what
  std::vector<std::string> calibration;  ///< where intrinsics, depth units, extrinsics come from
  std::vector<std::string> notes;        ///< facts the user must know (no IMU, no gyroscope, ...)

  // Counted by the converter.
  std::size_t color_images = 0, depth_images = 0;
  PairingStats pairing;                 ///< pairs, colour alone (dropped), depth alone
  std::size_t depth_alone_dropped = 0;  ///< depth without colour, dropped (require_colour)
  double pair_tolerance_s = 0.0;
  std::size_t imu_messages = 0;        ///< combined IMU messages read
  AccelGyroMergeStats merge;           ///< separate accelerometer/gyro streams
  std::size_t accel_only_samples = 0;  ///< accelerometer-only samples written (no gyroscope)
  std::size_t groundtruth_poses = 0;
  std::size_t odometry_messages = 0;     ///< nav_msgs/Odometry messages decoded and delivered
  std::size_t unreadable = 0;            ///< messages / files that could not be decoded (skipped)
  std::size_t depth_clipped_pixels = 0;  ///< float depth beyond 16 bits of the output unit
  std::size_t stamps_from_bag_time = 0;  ///< messages with a zero header stamp (bag time used)

  // Counted by the writer.
  std::size_t frames_written = 0, imu_written = 0, groundtruth_written = 0, wheel_written = 0;
  std::size_t dropped_by_ordering = 0;  ///< late or duplicate stamps beyond the re-ordering window
  std::vector<std::string> outputs;     ///< files written

  std::string error;  ///< why the conversion stopped early ("" = complete)
  double wall_time_s = 0.0;
  std::uint64_t input_bytes = 0;

  /// Records a message of a kind ("unreadable", "ordering", ...); at most `max_listed` are kept
  /// per kind, the rest only counted.
  void addIssue(const std::string& kind, const std::string& message, int max_listed);
  std::size_t issueCount(const std::string& kind) const;
  /// The messages kept of a kind (at most `max_listed`).
  std::vector<std::string> listedIssues(const std::string& kind) const;
  /// Adds the writer's counts, outputs and issues collected in `writer` to this report.
  void absorbWriter(const ConversionReport& writer, int max_listed);

  bool ok() const { return error.empty(); }
  /// The final report (several lines).
  std::string text() const;

 private:
  struct IssueList {
    std::size_t count = 0;
    std::vector<std::string> listed;
  };
  std::map<std::string, IssueList> issues_;
};

}  // namespace rgbdi::bag
