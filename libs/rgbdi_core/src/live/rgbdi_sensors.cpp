#include "rgbdi/live/rgbdi_sensors.h"

#include <mutex>

#include "rgbdi/live/rawlog_replay_sensor.h"
#include "rgbdi/live/realsense_sensor.h"
#include "rgbdi/live/simulator_sensor.h"

namespace rgbdi::live {

void registerRgbdiSensors() {
  // MRPT's registry is a process-wide map; registering twice is harmless, once is enough.
  static std::once_flag once;
  std::call_once(once, [] {
    RgbdiRawlogReplay::doRegister();
    RgbdiSimulator::doRegister();
    RgbdiRealSense::doRegister();
  });
}

std::vector<std::string> rgbdiSensorClassNames() {
  return {"RgbdiRawlogReplay", "RgbdiSimulator", "RgbdiRealSense"};
}

}  // namespace rgbdi::live
