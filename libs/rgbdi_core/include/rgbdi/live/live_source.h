// A MeasurementSource fed by live sensors: every sensor of a sensors INI (rawlog-grabber layout,
// see sensor_config.h) is created through MRPT's CGenericSensor class registry, configured
// (loadConfig), opened (initialize) and then grabs in its own thread at its process_rate.
//
// Threads and queues:
//  * one thread per sensor: doProcess(), getObservations(), conversion of each
//    CObservation3DRangeScan / CObservationIMU (io/mrpt_conversions), then, under the source's
//    lock, the time-ordering buffer (io/time_ordering_buffer, windows of [stream]);
//  * released measurements go into two bounded delivery queues, one per kind. When the RGB-D
//    queue is full the OLDEST waiting frame is dropped (counted); IMU samples are never dropped:
//    an IMU backlog beyond live_imu_queue_len ends the run with LiveError::Overload (memory stays
//    bounded);
//  * one watchdog thread: camera timeout, IMU stalls, the end of finite sensors (FiniteSensor);
//  * the consumer calls next() (or pump()), which merges the two queues in time order (IMU
//    first at equal stamps) and, when recording, writes each delivered measurement.
// Faults: a camera silent for live_camera_timeout_s (or no frame at all within
// live_first_frame_timeout_s), a sensor whose doProcess() throws or whose state becomes
// ssError, or the IMU overload stop grabbing; what was already received is still delivered, then
// next() throws LiveError (once) naming the section. IMU stalls and time jumps are counted and
// listed in stats(), the stream goes on.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "rgbdi/io/measurement_source.h"
#include "rgbdi/io/stream_options.h"
#include "rgbdi/live/live_error.h"
#include "rgbdi/live/live_stats.h"
#include "rgbdi/live/sensor_config.h"

namespace rgbdi::live {

/// Writing the delivered stream to a rawlog (external images) that `rgbdi-slam --input` reads.
struct RecordingOptions {
  std::string path;  ///< *.rawlog; images go to <dir>/<stem>_Images/
  /// Colour camera optical frame in the body frame, stored as every frame's sensorPose (the
  /// run's [extrinsic] T_body_cam).
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
};

class LiveSource : public io::MeasurementSource {
 public:
  /// Creates, configures and opens every sensor (registers rgbdi's own sensor classes first).
  /// Throws LiveError: UnknownDriver (names the section and the class), OpenFailed (names the
  /// section, the driver and the sensor's reason). Grabbing starts with start() or the first
  /// next().
  LiveSource(const SensorConfig& sensors, const io::StreamConfig& stream = io::StreamConfig());
  /// Stops and joins every thread; closes the recording (keeping what was written).
  ~LiveSource() override;
  LiveSource(const LiveSource&) = delete;
  LiveSource& operator=(const LiveSource&) = delete;

  /// Records every delivered measurement; call before start(). Throws IoError when the rawlog
  /// cannot be created.
  void record(const RecordingOptions& options);
  /// Starts the sensor threads and the watchdog (idempotent).
  void start();

  bool next(io::Measurement& out) override;
  /// Stops grabbing (sensor threads are joined); what was received is still delivered. May be
  /// called from any thread, also while another thread waits in next().
  void stopReading() override;
  /// Checks of the delivered stream (as for rawlogs); complete at the end of the stream.
  const io::StreamDiagnostics& diagnostics() const override;

  /// A consistent snapshot (thread-safe, may be called while the stream runs).
  LiveStats stats() const;
  const SensorConfig& config() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::live
