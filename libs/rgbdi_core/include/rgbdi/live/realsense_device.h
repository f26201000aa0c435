// The small interface between the RgbdiRealSense sensor and a RealSense D4xx device, so that
// everything around the SDK compiles and is tested without it. Implementations:
//  * the SDK adapter (librealsense2; compiled only when CMake finds realsense2, see
//    realSenseSdkAvailable()): a camera, or an SDK .bag in the SDK's own playback mode;
//  * the recorded adapter (always built): replays a RealSense SDK .bag recording with rgbdi's
//    bag reader at its native rates, calling the same callbacks.
// Conventions: stamps in seconds on the host clock where the device provides it (SDK global
// time), colour CV_8UC3 R,G,B, depth CV_16UC1 in units of depth_unit_m, accelerometer [m/s^2]
// and gyro [rad/s] in the IMU frame of the device.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/common/camera.h"

namespace rgbdi::live {

class RealSenseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct RealSenseDeviceInfo {
  std::string name, serial, firmware;
};

/// What to stream and the device options (the RgbdiRealSense keys).
struct RealSenseRequest {
  std::string serial;                                         ///< "" = the first device found
  int color_width = 640, color_height = 480, color_fps = 30;  ///< [px], [px], [Hz]
  int depth_width = 640, depth_height = 480, depth_fps = 30;  ///< [px], [px], [Hz]
  int accel_hz = 250;                                         ///< [Hz] 63 or 250 on a D435i
  int gyro_hz = 200;                                          ///< [Hz] 200 or 400 on a D435i
  bool imu = true;                    ///< stream accel + gyro (off for a D435 without IMU)
  bool align_depth_to_color = false;  ///< register depth to the colour image in the adapter
  bool emitter_enabled = true;        ///< IR projector on (depth on untextured surfaces)
  bool depth_auto_exposure = true;
  bool color_auto_exposure = true;
  bool global_time = true;  ///< stamps on the host clock (SDK GLOBAL_TIME_ENABLED)
};

/// The device calibration the observations need.
struct RealSenseCalibration {
  PinholeCamera color, depth;  ///< depth = colour intrinsics when depth is aligned
  /// Pose of the depth optical frame in the colour optical frame (identity when aligned).
  Eigen::Isometry3d T_color_depth = Eigen::Isometry3d::Identity();
  /// Pose of the colour optical frame in the IMU frame (the body frame of rgbdi).
  Eigen::Isometry3d T_imu_color = Eigen::Isometry3d::Identity();
  bool has_imu = false;
  bool depth_aligned = false;
  double depth_unit_m = 1e-3;  ///< [m] per depth unit (SDK depth scale)
  RealSenseDeviceInfo device;
};

/// One colour + depth pair.
struct RealSenseFrameset {
  double t = 0.0;  ///< [s] colour stamp
  std::uint64_t number = 0;
  cv::Mat rgb;    ///< CV_8UC3 R,G,B (may be empty: depth only)
  cv::Mat depth;  ///< CV_16UC1 (may be empty: colour only)
};

struct RealSenseMotion {
  enum class Kind { Accel, Gyro };
  Kind kind = Kind::Gyro;
  double t = 0.0;  ///< [s]
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
};

class RealSenseDevice {
 public:
  using FramesetCallback = std::function<void(RealSenseFrameset&&)>;
  using MotionCallback = std::function<void(const RealSenseMotion&)>;

  virtual ~RealSenseDevice() = default;
  /// Devices that can be opened.
  virtual std::vector<RealSenseDeviceInfo> enumerate() = 0;
  /// Opens the device (or recording), configures streams and options; throws RealSenseError
  /// with the reason (no device, serial not found, unsupported profile, ...).
  virtual RealSenseCalibration open(const RealSenseRequest& request) = 0;
  /// Starts streaming; callbacks run on the adapter's threads and must return quickly.
  virtual void start(FramesetCallback on_frameset, MotionCallback on_motion) = 0;
  /// Stops streaming; no callback runs after it returns. Idempotent.
  virtual void stop() = 0;
  /// True once a recording has delivered everything (always false for a camera).
  virtual bool finished() const = 0;
  /// Why streaming ended early (device lost, damaged recording); "" when it did not.
  virtual std::string error() const = 0;
};

/// True when rgbdi was built with librealsense2.
bool realSenseSdkAvailable();
/// The SDK adapter; `playback_bag` non-empty plays an SDK recording through the SDK's own
/// playback (in real time at `speed`, stamps re-based onto the wall clock when `restamp`; both
/// unused for a camera). Throws RealSenseError when rgbdi was built without librealsense2.
std::unique_ptr<RealSenseDevice> makeSdkRealSenseDevice(const std::string& playback_bag = "",
                                                        double speed = 1.0, bool restamp = false);
/// The recorded adapter: replays an SDK .bag with rgbdi's bag reader, paced by its stamps at
/// `speed`; stamps are re-based onto the wall clock when `restamp`. `options` and `fallback` as
/// for rawlog-convert (--config's [convert], [camera] and [extrinsic], --camera-yaml): pairing,
/// depth units and the calibration the recording does not carry.
std::unique_ptr<RealSenseDevice> makeRecordedRealSenseDevice(
    const std::string& bag_path, double speed, bool restamp,
    const bag::ConvertOptions& options = bag::ConvertOptions(),
    const bag::FallbackCalibration& fallback = bag::FallbackCalibration::defaults());

}  // namespace rgbdi::live
