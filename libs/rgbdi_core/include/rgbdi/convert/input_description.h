// `rawlog-convert --info` for inputs that are not rawlogs: the topics of a ROS1 bag (type, count,
// rate) with the layout and calibration a conversion would use, or the lists of a TUM RGB-D folder.
#pragma once

#include <string>

#include "rgbdi/convert/dataset_conversion.h"

namespace rgbdi::convert {

struct InputDescription {
  std::string text;   ///< human-readable summary
  std::string json;   ///< the same as one JSON object
  std::string error;  ///< damage found (the description covers what is readable); "" = none
};

/// Describes a bag or TUM folder. Throws IoError / bag::BagError when it cannot be read at all.
InputDescription describeBag(const std::string& path, const ConversionSettings& settings,
                             const bag::TopicOverrides& topics);
InputDescription describeTumFolder(const std::string& path);

}  // namespace rgbdi::convert
