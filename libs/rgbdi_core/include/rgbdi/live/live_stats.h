// What a live run measured: per kind received / delivered / dropped, queue high-water marks,
// latency from sensor stamp to delivery, IMU stalls and time jumps, per-sensor counts.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "rgbdi/live/latency_histogram.h"

namespace rgbdi::live {

struct SensorCounts {
  std::string section, driver;
  std::size_t imu = 0, frames = 0;  ///< observations received from this sensor
  std::size_t other = 0;            ///< observations of other types (ignored)
  std::size_t unusable = 0;         ///< RGB-D / IMU observations that could not be converted
  bool ended = false;               ///< a finite sensor that reached its end
};

struct LiveStats {
  std::size_t imu_received = 0, imu_delivered = 0;
  std::size_t frames_received = 0, frames_delivered = 0;
  /// Frames removed from the delivery queue because the consumer was behind.
  std::size_t frames_dropped = 0;
  /// Measurements the time-ordering buffer rejected (late, duplicate, invalid stamp).
  std::size_t imu_rejected = 0, frames_rejected = 0;
  std::size_t imu_queue_high_water = 0;    ///< [samples] most IMU samples waiting at once
  std::size_t frame_queue_high_water = 0;  ///< [frames] most frames waiting at once
  std::size_t ordering_high_water = 0;     ///< most measurements in the re-ordering window
  /// Wall-clock delivery time minus the measurement's stamp. Meaningful when stamps are on the
  /// host clock (RealSense global time, replay/simulator with stamps = now).
  LatencySummary imu_latency, frame_latency;
  std::size_t imu_stalls = 0;      ///< periods of more than live_imu_stall_s without IMU data
  std::size_t imu_time_jumps = 0;  ///< consecutive IMU stamps more than live_imu_time_jump_s apart
                                   ///< or going backwards (per sensor)
  std::vector<std::string>
      events;  ///< stall / jump / fault messages (at most live_max_listed_events)
  std::vector<SensorCounts> sensors;
  double wall_duration_s = 0.0;  ///< [s] from start() to now / to the end of the stream
  std::string error;             ///< why the stream ended early; "" when it did not

  /// One JSON object with these fields (for summary.json).
  std::string toJson(int indent = 2) const;
  /// One line for a progress display: rates, drops, latency.
  std::string line() const;
};

}  // namespace rgbdi::live
