// RgbdiSimulator: rgbdi's simulator (sim::SimulatedSequence) as a live sensor, paced in real
// time: doProcess() appends every IMU sample and wheel-odometry reading (CObservationOdometry,
// the simulated encoders of the wheeled and tracked profiles) and renders every frame whose stamp
// is due (t <= t0 + (wall - wall0) * speed; playback starts at the first doProcess()). Frames are
// rendered in the sensor's thread; a frame that is already more than max_frame_lateness_s late
// when its turn comes is skipped (counted), as a camera loses frames its host cannot take, so a
// machine slower than the frame rate gets fewer frames, not a growing delay.
//
// Keys of its section (besides driver and process_rate, which should be >= the frame rate):
//   profile      = wheeled_circle   handheld | wheeled_circle | wheeled_slopes | tracked_slopes
//   duration_s   = 0       [s] sequence length (0: the profile's)
//   speed_preset = normal  slow | normal | fast (the profile's cruise speed)
//   fps          = 0       [Hz] frame rate (0: [sim] fps of `config`, default 30)
//   seed         = -1      noise seed (-1: [sim] seed of `config`)
//   config       =         rgbdi INI with [sim], [camera] (image size, intrinsics), [extrinsic]
//   speed        = 1.0     [sim s / wall s] playback speed
//   stamps       = now     now: stamps on the wall clock; source: the simulator's own stamps
//   max_frame_lateness_s = 0.1  [s] later frames are skipped (rendering slower than real time)
//   wheel_encoders = auto  off | on | auto (the wheeled and tracked profiles): the simulated
//                          encoders; replaces [sim] wheel_encoders of `config`, whose other
//                          [sim] wheel_* keys give the model (the readings rgbdi-sim writes)
//   camera_label = RGBD, imu_label = IMU, wheel_label = WHEEL_ODOMETRY
#pragma once

#include <mrpt/hwdrivers/CGenericSensor.h>

#include <memory>

#include "rgbdi/live/finite_sensor.h"

namespace rgbdi::live {

class RgbdiSimulator : public mrpt::hwdrivers::CGenericSensor, public FiniteSensor {
  DEFINE_GENERIC_SENSOR(RgbdiSimulator)

 public:
  RgbdiSimulator();
  ~RgbdiSimulator() override;

  /// Builds the sequence (scene, trajectory, IMU); throws on inconsistent options.
  void initialize() override;
  void doProcess() override;
  bool endOfData() const override;
  /// Frames skipped because rendering was behind (thread-safe).
  std::size_t framesSkipped() const;
  void setPathForExternalImages(const std::string& directory) override;

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::live
