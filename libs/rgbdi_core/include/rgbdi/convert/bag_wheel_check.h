// `rawlog-convert --info` on a bag with wheel odometry: the odometry and IMU topics are read
// (nothing else), converted as a conversion would convert them, put in time order and checked by
// the same StreamChecker that checks a rawlog's wheel stream: rate, gaps, the readings that move
// while the IMU is at rest and those that stand while it moves ([stream] wheel_*). Its messages
// name "<bag> record N": the N-th IMU or odometry message read (from 0).
#pragma once

#include <string>

#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/io/stream_diagnostics.h"
#include "rgbdi/io/stream_options.h"

namespace rgbdi::convert {

/// The diagnostics of the bag's odometry (wheel) and IMU (imu) streams. Throws bag::BagError
/// when the bag cannot be converted (layout, calibration). Messages that cannot be decoded are
/// counted in `unusable` and listed in `warnings`; damage ends the check with `error` set.
io::StreamDiagnostics checkBagWheels(const std::string& path, const ConversionSettings& settings,
                                     const bag::TopicOverrides& topics,
                                     const io::StreamConfig& config);

}  // namespace rgbdi::convert
