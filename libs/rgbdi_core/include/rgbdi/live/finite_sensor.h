// Optional interface of a CGenericSensor whose data ends (a file played back, a simulated
// sequence). LiveSource ends the stream normally once every finite sensor has ended; MRPT's
// rawlog-grabber does not know it and simply receives nothing more.
#pragma once

namespace rgbdi::live {

class FiniteSensor {
 public:
  virtual ~FiniteSensor() = default;
  /// True once the sensor has appended its last observation (thread-safe).
  virtual bool endOfData() const = 0;
};

}  // namespace rgbdi::live
