// Which RealSense adapters this build has: the SDK one only when CMake found librealsense2
// (RGBDI_HAVE_REALSENSE2, src/live_sdk/); the recorded one always.
#include "rgbdi/live/realsense_device.h"

namespace rgbdi::live {

#ifdef RGBDI_HAVE_REALSENSE2
std::unique_ptr<RealSenseDevice> makeLibrealsenseDevice(const std::string& playback_bag,
                                                        double speed, bool restamp);
#endif

bool realSenseSdkAvailable() {
#ifdef RGBDI_HAVE_REALSENSE2
  return true;
#else
  return false;
#endif
}

std::unique_ptr<RealSenseDevice> makeSdkRealSenseDevice(const std::string& playback_bag,
                                                        double speed, bool restamp) {
#ifdef RGBDI_HAVE_REALSENSE2
  return makeLibrealsenseDevice(playback_bag, speed, restamp);
#else
  (void)playback_bag;
  (void)speed;
  (void)restamp;
  throw RealSenseError(
      "rgbdi was built without librealsense2, so it cannot drive a RealSense camera: install "
      "the SDK and rebuild (doc/live.md), or play a recording with device = recorded");
#endif
}

}  // namespace rgbdi::live
