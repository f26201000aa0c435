// rgbdi's own CGenericSensor classes: RgbdiRawlogReplay, RgbdiSimulator, RgbdiRealSense.
// registerRgbdiSensors() adds them to MRPT's sensor class registry (idempotent). LiveSource calls
// it; the rawlog-grabber plugin calls it when it is loaded.
#pragma once

#include <string>
#include <vector>

namespace rgbdi::live {

void registerRgbdiSensors();
/// Names of rgbdi's sensor classes (for messages).
std::vector<std::string> rgbdiSensorClassNames();

}  // namespace rgbdi::live
