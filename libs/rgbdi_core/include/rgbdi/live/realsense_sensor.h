// RgbdiRealSense: an Intel RealSense D435i / D455 as an MRPT sensor. The device sits behind
// RealSenseDevice (realsense_device.h): the librealsense2 adapter for a camera (only when rgbdi is
// built with the SDK), or the recorded adapter that plays a RealSense SDK .bag without the SDK.
// Colour + depth framesets become CObservation3DRangeScan with both intrinsics and the
// colour/depth relative pose from the device calibration (depth aligned or not); accelerometer
// and gyro samples are merged at the gyro stamps (bag::AccelGyroMerger, accel interpolated) into
// CObservationIMU. The IMU is the body frame: IMU observations have an identity sensorPose and the
// camera's sensorPose is the device's colour-to-IMU extrinsic.
//
// Keys of its section (besides driver and process_rate, e.g. 200):
//   device        = sdk      sdk: librealsense2 (camera, or playback_file through the SDK);
//                            recorded: rgbdi's reader plays playback_file (no SDK needed)
//   playback_file =          RealSense SDK .bag (relative to the INI's directory)
//   serial        =          camera serial number ("" = the first camera)
//   color_width = 640, color_height = 480, color_fps = 30     [px] [px] [Hz]
//   depth_width = 640, depth_height = 480, depth_fps = 30     [px] [px] [Hz]
//   imu = true, accel_hz = 250, gyro_hz = 200                 [Hz]
//   align_depth = false      register depth to colour in the driver (SDK adapter only)
//   emitter_enabled = true, depth_auto_exposure = true, color_auto_exposure = true
//   global_time = true       stamps on the host clock (SDK global time)
//   max_accel_gap_s = 0.05   [s] no accelerometer interpolation across larger gaps
//   max_merge_wait_s = 0.1   [s] a gyro sample waits at most this for its accel partner
//   frameset_queue_len = 8   [framesets] received but not yet turned into observations;
//                            older ones are dropped (counted) if the thread falls behind
//   speed = 1.0, stamps = now  playback (either adapter): playback speed, now|source stamps
//   config = FILE, camera_yaml = FILE   device = recorded only: rgbdi INI / VINS yaml as
//                            rawlog-convert's --config / --camera-yaml ([convert] pairing and
//                            depth units; calibration the recording does not carry)
//   camera_label = RGBD, imu_label = IMU
#pragma once

#include <mrpt/hwdrivers/CGenericSensor.h>

#include <memory>

#include "rgbdi/bag/accel_gyro_merger.h"
#include "rgbdi/live/finite_sensor.h"
#include "rgbdi/live/realsense_device.h"

namespace rgbdi::live {

/// Counters of the driver (thread-safe snapshot).
struct RealSenseSensorStats {
  std::size_t framesets = 0, framesets_dropped = 0;
  std::size_t accel = 0, gyro = 0;
  bag::AccelGyroMergeStats merge;
};

class RgbdiRealSense : public mrpt::hwdrivers::CGenericSensor, public FiniteSensor {
  DEFINE_GENERIC_SENSOR(RgbdiRealSense)

 public:
  RgbdiRealSense();
  ~RgbdiRealSense() override;

  /// Uses `device` instead of the adapter the keys select (other adapters, tests); call
  /// before initialize().
  void setDevice(std::unique_ptr<RealSenseDevice> device);
  /// Opens and starts the device; throws naming the reason (e.g. built without the SDK).
  void initialize() override;
  void doProcess() override;
  /// The recorded adapter has played everything and every sample has been appended.
  bool endOfData() const override;
  void setPathForExternalImages(const std::string& directory) override;

  const RealSenseRequest& request() const;
  /// Valid after initialize().
  const RealSenseCalibration& calibration() const;
  RealSenseSensorStats stats() const;

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::live
