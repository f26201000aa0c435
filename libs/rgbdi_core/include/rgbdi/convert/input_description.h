// `rawlog-convert --info` for inputs that are not rawlogs: the topics of a ROS1 bag (type, count,
// rate) with the layout and calibration a conversion would use and the checks of its wheel
// odometry, or the lists of a TUM RGB-D folder.
#pragma once

#include <string>

#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/io/stream_options.h"

namespace rgbdi::convert {

struct InputDescription {
  std::string text;   ///< human-readable summary
  std::string json;   ///< the same as one JSON object
  std::string error;  ///< damage found (the description covers what is readable); "" = none
};

/// Describes a bag or TUM folder. Throws IoError / bag::BagError when it cannot be read at all.
/// A bag with wheel odometry also gets its wheel stream checked (bag_wheel_check.h) with the
/// [stream] options of `stream`.
InputDescription describeBag(const std::string& path, const ConversionSettings& settings,
                             const bag::TopicOverrides& topics,
                             const io::StreamConfig& stream = {});
InputDescription describeTumFolder(const std::string& path);

}  // namespace rgbdi::convert
