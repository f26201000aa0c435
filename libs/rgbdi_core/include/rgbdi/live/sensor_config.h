// The sensors INI of a live run, in MRPT rawlog-grabber layout: every section except [global] is
// one sensor (`driver = CLASSNAME`, `process_rate = HZ`, then the driver's own keys), so the same
// file works with Debian's `rawlog-grabber -p librgbdi_mrpt_sensors.so FILE`. The live source's
// own settings are `live_*` keys of [global] (rawlog-grabber ignores keys it does not know);
// rawlog-grabber's [global] keys are accepted and not used. A section with
// `rawlog-grabber-ignore = true` is skipped, as rawlog-grabber does.
#pragma once

#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::live {

/// [global] live_* keys: queues, timeouts and checks of LiveSource.
struct LiveOptions {
  int image_queue_len = 3;        ///< [frames] RGB-D frames waiting for the consumer; older dropped
  int imu_queue_len = 4000;       ///< [samples] IMU backlog beyond which the run stops (Overload)
  double camera_timeout_s = 2.0;  ///< [s] no frame from a camera sensor: error, stream ends
  double first_frame_timeout_s = 10.0;  ///< [s] no frame from any sensor since start: same
  double imu_stall_s = 0.1;       ///< [s] (wall clock) no IMU sample arrived: a stall is reported
  double imu_time_jump_s = 0.05;  ///< [s] consecutive IMU stamps further apart: a jump is reported
  double watchdog_period_s = 0.01;  ///< [s] how often timeouts and stalls are checked
  int max_listed_events = 20;       ///< stall/jump messages kept; further ones only counted

  static LiveOptions load(IniReader& ini);
};

/// One sensor section.
struct SensorSection {
  std::string name;              ///< section name (also the default sensor label)
  std::string driver;            ///< CGenericSensor class name
  double process_rate_hz = 0.0;  ///< [Hz] rate of the sensor's grabbing thread
};

struct SensorConfig {
  std::string path;  ///< the INI file, "" when built from text
  std::string text;  ///< its content (used when path is "")
  LiveOptions live;
  std::vector<SensorSection> sensors;

  /// Reads and checks the file: at least one sensor, each with a driver and a process_rate > 0,
  /// valid live_* keys, no unknown [global] keys. Throws ConfigError naming file, section, key.
  static SensorConfig fromFile(const std::string& path);
  /// The same for INI text (`label` stands for the file name in messages).
  static SensorConfig fromText(const std::string& text, const std::string& label);
};

}  // namespace rgbdi::live
