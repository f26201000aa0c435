// RgbdiRawlogReplay: plays a recording as a live sensor, paced by its stamps. Input: an MRPT
// rawlog (read with io::RawlogSource: both layouts, gzip, external images; its wheel odometry
// is replayed too) or a ROS1 bag that
// rawlog-convert reads (RealSense SDK recording, VINS-RGBD dataset layout, other topics;
// converted on the fly with bag::BagConverter as rawlog-convert converts it with the equivalent
// options below). A reader thread fills a
// bounded read-ahead queue (it waits when the queue is full: a file is never dropped from);
// doProcess() appends every measurement whose stamp is due: t <= t0 + (wall - wall0) * speed,
// where playback starts at the first doProcess().
//
// Keys of its section (besides driver and process_rate, which should be >= the camera rate):
//   file       = PATH     the rawlog or bag (relative to the INI file's directory)
//   speed      = 1.0      [data s / wall s] playback speed
//   stamps     = now      now: re-stamped onto the wall clock; source: the recorded stamps
//   read_ahead = 256      [measurements] read-ahead queue length
//   camera_label = RGBD, imu_label = IMU, wheel_label = WHEEL_ODOMETRY   sensorLabel of the
//                      observations
// ROS1 bags only (an error with a rawlog; see live/bag_playback_keys.h):
//   config = FILE       rgbdi INI as rawlog-convert --config ([camera], [extrinsic] where the bag
//                       has none; [convert] pairing, waits, depth units, require_colour)
//   camera_yaml = FILE  VINS yaml as rawlog-convert --camera-yaml
//   depth_aligned = auto|yes|no, color_topic, depth_topic, imu_topic, accel_topic, gyro_topic,
//   color_info_topic, depth_info_topic    as rawlog-convert's --depth-aligned and --*-topic
#pragma once

#include <mrpt/hwdrivers/CGenericSensor.h>

#include <memory>

#include "rgbdi/live/finite_sensor.h"

namespace rgbdi::live {

class RgbdiRawlogReplay : public mrpt::hwdrivers::CGenericSensor, public FiniteSensor {
  DEFINE_GENERIC_SENSOR(RgbdiRawlogReplay)

 public:
  RgbdiRawlogReplay();
  ~RgbdiRawlogReplay() override;

  /// Opens the input (throws naming the file and why) and starts the reader thread.
  void initialize() override;
  void doProcess() override;
  bool endOfData() const override;
  void setPathForExternalImages(const std::string& directory) override;

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::live
