// librgbdi_mrpt_sensors.so: rgbdi's sensor classes for MRPT programs that load plugins, e.g.
//   rawlog-grabber -p build/lib/librgbdi_mrpt_sensors.so share/sensors/simulator.ini
// Loading the library registers RgbdiRawlogReplay, RgbdiSimulator and RgbdiRealSense with
// MRPT's CGenericSensor registry (the same registry rawlog-grabber looks `driver = ...` up in).
#include <mrpt/core/initializer.h>

#include "rgbdi/live/rgbdi_sensors.h"

MRPT_INITIALIZER(rgbdi_register_mrpt_sensors) { rgbdi::live::registerRgbdiSensors(); }
