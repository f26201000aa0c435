// The typed errors of the live stage. Every message names the sensors-INI file and the sensor
// section it is about, so a user knows which device or line to fix.
#pragma once

#include <stdexcept>
#include <string>

namespace rgbdi::live {

class LiveError : public std::runtime_error {
 public:
  enum class Kind {
    Config,         ///< the sensors INI is invalid (missing driver, bad value)
    UnknownDriver,  ///< `driver = X` names no registered CGenericSensor class
    OpenFailed,     ///< loadConfig() or initialize() of a sensor threw
    SensorFailed,   ///< doProcess() threw or the sensor reported ssError while running
    CameraTimeout,  ///< no RGB-D frame for camera_timeout_s
    Overload,       ///< the consumer fell so far behind that even the IMU backlog overflowed
  };
  LiveError(Kind kind, std::string section, const std::string& message)
      : std::runtime_error(message), kind_(kind), section_(std::move(section)) {}

  Kind kind() const { return kind_; }
  /// The sensor section concerned ("" when the error is not about one sensor).
  const std::string& section() const { return section_; }

 private:
  Kind kind_;
  std::string section_;
};

}  // namespace rgbdi::live
