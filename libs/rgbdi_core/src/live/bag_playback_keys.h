// The sensor keys with which a sensor that plays a ROS1 bag (RgbdiRawlogReplay on a bag,
// RgbdiRealSense with device = recorded) converts it as rawlog-convert does with the equivalent
// options, so that a bag played live and the same bag converted give the same observations:
//   config      = FILE  rgbdi INI, as rawlog-convert --config: [camera] intrinsics and
//                       [extrinsic] used where the bag has none, [convert] settings
//                       (pair_tolerance_s, max_wait_s, depth units, require_colour, ...)
//   camera_yaml = FILE  VINS-Mono / VINS-RGBD yaml, as --camera-yaml: intrinsics and extrinsic,
//                       over config's
// and, with `with_topics` (the replay; a RealSense recording has the SDK's fixed layout):
//   depth_aligned = auto|yes|no   as --depth-aligned (auto: the layout's default)
//   color_topic, depth_topic, imu_topic, accel_topic, gyro_topic, color_info_topic,
//   depth_info_topic              as --color-topic ... ("" automatic, "none" unused)
// Files are relative to the sensors INI; their errors name the sensor key and the file.
#pragma once

#include <string>
#include <vector>

#include "live/sensor_keys.h"
#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/convert/dataset_conversion.h"

namespace rgbdi::live {

struct BagPlaybackKeys {
  convert::ConversionSettings settings;  ///< [convert] options and the fallback calibration
  bag::BagInputOptions input;            ///< topics and depth alignment
  std::vector<std::string> given;        ///< the keys present in the section, in key order

  /// Reads and validates the keys (loads the files); throws ConfigError naming the key.
  static BagPlaybackKeys load(const SensorKeys& k, bool with_topics);
  /// "config, camera_yaml" (the keys present), for refusing them where they do not apply.
  std::string givenList() const;
};

}  // namespace rgbdi::live
