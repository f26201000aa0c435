// Writes a simulated sequence to disk (what `rgbdi-sim` produces), streaming frame by frame:
//
//   DIR/sequence.rawlog        observations-only rawlog: CObservation3DRangeScan (colour +
//                              depth in mm, both cameras' intrinsics, cameras coincide) and
//                              CObservationIMU (and CObservationOdometry when the wheel
//                              encoders are on), in time order
//   DIR/sequence_Images/       colour as PNG, depth as MRPT external range files (unless the
//                              images are embedded in the rawlog: external_images = false)
//   DIR/groundtruth.tum        body (IMU) frame at every IMU sample (IMU clock)
//   DIR/groundtruth_cam.tum    colour camera frame at every image (image stamps)
//   DIR/config.ini             [camera] [imu] [extrinsic] for rgbdi-slam: the camera and
//                              extrinsic used, IMU noise densities inflated (never the truth)
//   DIR/simulation.ini         every setting used ([sim] [camera] [extrinsic]; pass it back as
//                              --config to regenerate the sequence) and the true initial biases
//   DIR/sequence.bag           optional ROS1 bag in the published dataset layout (with the
//                              encoders: /odom nav_msgs/Odometry and /tf_static base_link in
//                              the IMU frame)
//   DIR/vins_config.yaml       with the bag: its VINS-RGBD calibration file (camera, extrinsic,
//                              the config.ini IMU noise as VINS values, td 0), which
//                              `rawlog-convert --camera-yaml` turns into an rgbdi configuration
//
// Rawlog and bag are written under temporary names and renamed when complete.
#pragma once

#include <atomic>
#include <ostream>
#include <string>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {

struct SequenceWriterOptions {
  bool write_bag = false;
  /// Images as files beside the rawlog (MRPT's layout for large datasets: the reader decodes a
  /// PNG and a compressed range file per frame), or raw inside the rawlog (as a live camera or
  /// a bag delivers them: nothing to decode; 1.5 MB per 640x480 frame).
  bool external_images = true;
  bag::Compression bag_compression = bag::Compression::None;
  /// Where the progress line goes (nullptr: silent). On a terminal (`progress_interactive`) it
  /// is redrawn in place every progress_interval_s [s of wall-clock time]; otherwise one line
  /// per tenth of the frames at most (ProgressGate).
  std::ostream* progress = nullptr;
  bool progress_interactive = false;
  double progress_interval_s = 1.0;
};

struct SequenceWriteSummary {
  bool completed = false;  ///< false when stopped early (no rawlog/bag is left then)
  std::size_t frames = 0, imu_samples = 0, wheel_readings = 0;
  double wall_time_s = 0.0;
  std::string rawlog_path, bag_path, groundtruth_path, groundtruth_cam_path, config_path,
      simulation_path, vins_config_path;
};

/// The content of DIR/config.ini for a sequence (see above).
std::string slamConfigText(const SimulatedSequence& sequence);
/// The content of DIR/vins_config.yaml for a sequence (see above).
std::string vinsConfigText(const SimulatedSequence& sequence);
/// The content of DIR/simulation.ini for a sequence (see above).
std::string simulationSettingsText(const SimulatedSequence& sequence);

/// Writes everything into out_dir (created if needed). Throws IoError / bag::BagError naming the
/// file on any write failure. When *stop becomes true, stops after the current measurement and
/// returns with completed = false (temporary rawlog/bag removed; images written so far remain).
SequenceWriteSummary writeSequence(const SimulatedSequence& sequence, const std::string& out_dir,
                                   const SequenceWriterOptions& options,
                                   const std::atomic<bool>* stop = nullptr);

}  // namespace rgbdi::sim
