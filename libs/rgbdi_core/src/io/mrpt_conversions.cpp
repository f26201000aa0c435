#include "rgbdi/io/mrpt_conversions.h"

#include <mrpt/img/CImage.h>
#include <mrpt/system/filesystem.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "rgbdi/common/whole_file.h"
#include "rgbdi/io/image_decode.h"

namespace rgbdi::io {
namespace {

/// MRPT stores rangeUnits as float; 0.001f widened to double is 0.0010000000474974513. Return
/// the shortest decimal that maps back to the same float, so that millimetre depth is exactly
/// 1e-3 m downstream and toMrpt() reproduces the original float bit for bit.
double cleanFloat(float f) {
  for (int digits = 6; digits <= 9; ++digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, static_cast<double>(f));
    const double d = std::strtod(buf, nullptr);
    if (static_cast<float>(d) == f) return d;
  }
  return static_cast<double>(f);
}

/// A flag MRPT read from the file: its CArchive reads a bool as the stored byte, so a damaged
/// record leaves values other than 0 and 1 in it, and reading those as bool is undefined
/// behaviour (UBSan in fuzz_replay_rawlog: "load of value 54, which is not a valid value for
/// type 'bool'"; optimised code may then take the flag as set and as not set). The byte is read
/// as a byte, and anything but 0 or 1 is refused as damage.
unsigned char storedByte(const bool& flag) {
  static_assert(sizeof(bool) == 1, "MRPT serialises a bool as one byte");
  unsigned char byte;
  std::memcpy(&byte, &flag, 1);
  return byte;
}
[[noreturn]] void throwDamagedFlag(const std::string& what, unsigned char byte) {
  throw ConversionError(what + " is stored as " + std::to_string(byte) +
                        ", which is no bool (0 or 1): the record is damaged");
}
bool storedFlag(const bool& flag, const std::string& what) {
  const unsigned char byte = storedByte(flag);
  if (byte > 1) throwDamagedFlag(what, byte);
  return byte == 1;
}

/// The protected flags MRPT reads from the file as bytes too (fuzzing finding 15: UBSan "load of
/// value 8, which is not a valid value for type 'bool'" in rangeImage_isExternallyStored()),
/// reached as members of a derived class so that storedFlag() reads their bytes.
struct ScanFlags : mrpt::obs::CObservation3DRangeScan {
  static bool mrpt::obs::CObservation3DRangeScan::*rangeExternal() {
    return &ScanFlags::m_rangeImage_external_stored;
  }
  static bool mrpt::obs::CObservation3DRangeScan::*pointsExternal() {
    return &ScanFlags::m_points3D_external_stored;
  }
};
struct ImageFlags : mrpt::img::CImage {
  static bool mrpt::img::CImage::*external() { return &ImageFlags::m_imgIsExternalStorage; }
};

cv::Mat colorToRgb(const mrpt::img::CImage& img, bool external, const std::string& label) {
  // External 8-bit PNGs (the usual layout) are decoded here straight to RGB; anything else, and
  // damaged files, take MRPT's lazy load (OpenCV), which also names the problem.
  if (external) {
    thread_local std::vector<std::uint8_t> bytes;
    const std::string file = img.getExternalStorageFileAbsolutePath();
    if (readWholeFile(file, bytes) == FileReadError::kNone) {
      try {
        if (auto rgb = decodePngToRgb(bytes.data(), bytes.size())) return std::move(*rgb);
      } catch (const ImageDecodeError& e) {
        throw ConversionError(label + ": intensity image " + file + ": " + e.what());
      }
    }
  }
  // asCvMatRef() triggers the lazy load of externally stored images.
  const cv::Mat& m = img.asCvMatRef();
  if (m.empty()) throw ConversionError(label + ": intensity image is empty");
  if (m.depth() != CV_8U) {
    throw ConversionError(label + ": intensity image has " + std::to_string(m.elemSize1() * 8) +
                          "-bit pixels; only 8-bit grey or colour images are supported");
  }
  cv::Mat rgb;
  switch (m.channels()) {
    case 1:
      cv::cvtColor(m, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(m, rgb, cv::COLOR_BGR2RGB);
      break;  // CImage keeps OpenCV's BGR
    case 4:
      cv::cvtColor(m, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      throw ConversionError(label + ": intensity image has " + std::to_string(m.channels()) +
                            " channels; expected 1, 3 or 4");
  }
  return rgb;
}

/// The observation's range matrix as CV_16UC1 (a copy).
cv::Mat rangeMatrix(const mrpt::obs::CObservation3DRangeScan& obs) {
  const auto& ri = obs.rangeImage;
  const int rows = static_cast<int>(ri.rows()), cols = static_cast<int>(ri.cols());
  cv::Mat m(rows, cols, CV_16UC1);
  for (int r = 0; r < rows; ++r) {
    auto* row = m.ptr<std::uint16_t>(r);
    for (int c = 0; c < cols; ++c) row[c] = ri(r, c);
  }
  return m;
}

/// `range` (CV_16UC1, the observation's range image) as depth along the optical axis.
cv::Mat rangeToDepth(const mrpt::obs::CObservation3DRangeScan& obs, cv::Mat range,
                     const PinholeCamera& cam_depth, const std::string& label) {
  const int rows = range.rows, cols = range.cols;
  if (rows == 0 || cols == 0) throw ConversionError(label + ": range image is empty (0x0)");
  if (storedFlag(obs.range_is_depth, label + ": range_is_depth")) return range;
  cv::Mat depth(rows, cols, CV_16UC1);
  // Euclidean ranges along each pixel's ray: depth = range / |(xn, yn, 1)|.
  if (!cam_depth.valid()) {
    throw ConversionError(label +
                          ": range image holds 3-D ranges (range_is_depth = false) but the depth "
                          "camera intrinsics (cameraParams) are missing, so they cannot be "
                          "converted to depth");
  }
  for (int r = 0; r < rows; ++r) {
    auto* row = depth.ptr<std::uint16_t>(r);
    const auto* in = range.ptr<std::uint16_t>(r);
    for (int c = 0; c < cols; ++c) {
      const std::uint16_t value = in[c];
      if (value == 0) {
        row[c] = 0;
        continue;
      }
      const Eigen::Vector2d xn = cam_depth.pixelToNormalized(Eigen::Vector2d(c, r));
      row[c] = static_cast<std::uint16_t>(std::lround(value / std::sqrt(1.0 + xn.squaredNorm())));
    }
  }
  return depth;
}

}  // namespace

double toSeconds(mrpt::Clock::time_point t) { return mrpt::Clock::toDouble(t); }

mrpt::Clock::time_point fromSeconds(double t) { return mrpt::Clock::fromDouble(t); }

Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const auto& R = p.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = R(r, c);
  T.translation() = Eigen::Vector3d(p.x(), p.y(), p.z());
  return T;
}

mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d R = T.linear();
  const Eigen::Vector3d t = T.translation();
  return mrpt::poses::CPose3D::FromRotationAndTranslation(R, t);
}

Eigen::Isometry3d mrptDepthFromOptical() {
  // Columns: optical x (right) = -Y_mrpt, optical y (down) = -Z_mrpt, optical z = +X_mrpt.
  // Written out exactly instead of via yaw/pitch/roll so that cos(90deg) round-off never leaks in.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1,  //
      -1, 0, 0,           //
      0, -1, 0;
  return T;
}

PinholeCamera fromMrpt(const mrpt::img::TCamera& cam, const std::string& label) {
  for (size_t i = 5; i < cam.dist.size(); ++i) {
    if (cam.dist[i] != 0.0) {
      throw ConversionError(
          label + ": camera '" + cam.cameraName + "' uses distortion coefficient " +
          std::to_string(i) +
          " (beyond k1 k2 p1 p2 k3); only the radial-tangential model is supported");
    }
  }
  PinholeCamera c;
  c.width = static_cast<int>(cam.ncols);
  c.height = static_cast<int>(cam.nrows);
  c.fx = cam.fx();
  c.fy = cam.fy();
  c.cx = cam.cx();
  c.cy = cam.cy();
  for (size_t i = 0; i < 5; ++i) c.dist[i] = cam.dist[i];
  return c;
}

mrpt::img::TCamera toMrpt(const PinholeCamera& cam) {
  mrpt::img::TCamera c;
  c.ncols = static_cast<uint32_t>(cam.width);
  c.nrows = static_cast<uint32_t>(cam.height);
  c.setIntrinsicParamsFromValues(cam.fx, cam.fy, cam.cx, cam.cy);
  c.dist.fill(0.0);
  for (size_t i = 0; i < 5; ++i) c.dist[i] = cam.dist[i];
  return c;
}

RgbdFrame fromMrpt(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label) {
  // The flags as read from the file are checked once; below only the checked copies are used.
  const bool has_intensity = storedFlag(obs.hasIntensityImage, label + ": hasIntensityImage");
  const bool has_range = storedFlag(obs.hasRangeImage, label + ": hasRangeImage");
  if (!has_intensity && !has_range)
    throw ConversionError(label + ": 3-D range scan has neither an intensity nor a range image");
  // MRPT's load() reads these too (only checked bytes reach it).
  const bool range_external =
      storedFlag(obs.*ScanFlags::rangeExternal(), label + ": the range image's external flag") &&
      has_range;
  (void)storedFlag(obs.hasPoints3D, label + ": hasPoints3D");
  (void)storedFlag(obs.*ScanFlags::pointsExternal(), label + ": the points' external flag");
  const bool intensity_external =
      has_intensity && storedFlag(obs.intensityImage.*ImageFlags::external(),
                                  label + ": the intensity image's external flag");

  RgbdFrame f;
  f.t = toSeconds(obs.timestamp);
  f.source_label = label;
  f.images_exclusive = true;  // every image below is decoded or converted into a new buffer
  // MRPT's own error for a missing external file is a bare "==== MRPT exception ====" banner:
  // name the file and the folder it was looked up in.
  auto requireFile = [&](const std::string& file, const char* what) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec))
      throw ConversionError(label + ": cannot load the observation's images: " + what + " " + file +
                            " does not exist (external images folder " +
                            mrpt::img::CImage::getImagesPathBase() + ")");
  };
  try {
    // Inside the try: MRPT asserts on a stored external file name it cannot resolve (fuzzing
    // finding 14: an empty name made lazy_load_absolute_path throw std::logic_error, which left
    // RawlogSource as an exception other than its documented RawlogError).
    if (range_external)
      requireFile(obs.rangeImage_getExternalStorageFileAbsolutePath(""), "range image");
    if (intensity_external)
      requireFile(obs.intensityImage.getExternalStorageFileAbsolutePath(), "intensity image");
    // An external binary range file not loaded yet is read here (libdeflate, image_decode.h);
    // otherwise, or when that fails, load() reads it (images load lazily on access).
    std::optional<cv::Mat> range;
    if (range_external && obs.rangeImage.rows() == 0) {
      const std::string file = obs.rangeImage_getExternalStorageFileAbsolutePath("");
      if (!mrpt::system::strCmpI(mrpt::system::extractFileExtension(file), "txt"))
        range = readMrptRangeFile(file);
    }
    if (!range) obs.load();
    f.cam_depth = fromMrpt(obs.cameraParams, label + " cameraParams");
    f.cam_color = fromMrpt(obs.cameraParamsIntensity, label + " cameraParamsIntensity");
    if (has_range) {
      if (!range) range = rangeMatrix(obs);
      // MRPT "auto-fixes" the depth intrinsics' size to the serialised matrix size, which is 0x0
      // for externally stored range images: restore it from the loaded matrix.
      if (range_external && f.cam_depth.width == 0 && f.cam_depth.height == 0) {
        f.cam_depth.width = range->cols;
        f.cam_depth.height = range->rows;
      }
      f.depth = rangeToDepth(obs, std::move(*range), f.cam_depth, label);
      f.depth_unit_m = cleanFloat(obs.rangeUnits);
      if (!(f.depth_unit_m > 0.0) || !std::isfinite(f.depth_unit_m)) {
        std::ostringstream os;
        os << label << ": rangeUnits = " << obs.rangeUnits << " is not a positive length in metres";
        throw ConversionError(os.str());
      }
    }
    if (has_intensity) f.rgb = colorToRgb(obs.intensityImage, intensity_external, label);
  } catch (const ConversionError&) {
    throw;
  } catch (const std::exception& e) {
    // MRPT reports missing external files etc. with multi-line traces ("==== MRPT exception
    // ====", "Message: ...", a call stack): keep the message line.
    std::string what = e.what();
    const auto message = what.find("Message:");
    if (message != std::string::npos) {
      what = what.substr(message + 8);
      what.erase(0, std::min(what.find_first_not_of(" \t"), what.size()));
    }
    const auto nl = what.find('\n');
    if (nl != std::string::npos) what.resize(nl);
    throw ConversionError(label + ": cannot load the observation's images: " + what);
  }

  f.depth_aligned_to_color = obs.doDepthAndIntensityCamerasCoincide();
  const Eigen::Isometry3d T_mrptdepth_color = toIsometry(obs.relativePoseIntensityWRTDepth);
  if (f.depth_aligned_to_color) {
    // Coinciding cameras: identity by definition (avoids 1e-17 noise from MRPT's yaw/pitch/roll).
    f.T_color_depth = Eigen::Isometry3d::Identity();
    f.source_T_body_cam = toIsometry(obs.sensorPose) * mrptDepthFromOptical();
  } else {
    f.T_color_depth = T_mrptdepth_color.inverse() * mrptDepthFromOptical();
    f.source_T_body_cam = toIsometry(obs.sensorPose) * T_mrptdepth_color;
  }
  f.has_source_T_body_cam = true;
  return f;
}

mrpt::obs::CObservation3DRangeScan::Ptr toMrpt(const RgbdFrame& frame,
                                               const Eigen::Isometry3d& T_body_cam,
                                               const std::string& sensorLabel) {
  auto obs = mrpt::obs::CObservation3DRangeScan::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = fromSeconds(frame.t);
  obs->cameraParams = toMrpt(frame.cam_depth);
  obs->cameraParamsIntensity = toMrpt(frame.cam_color);

  if (frame.depth_aligned_to_color) {
    const Eigen::Isometry3d& T = frame.T_color_depth;
    const double rot_err = (T.linear() - Eigen::Matrix3d::Identity()).norm();
    if (rot_err > 1e-9 || T.translation().norm() > 1e-9) {
      throw ConversionError(frame.source_label +
                            ": depth is declared aligned to colour but T_color_depth is not the "
                            "identity");
    }
    // Keep MRPT's own default value so that doDepthAndIntensityCamerasCoincide() holds exactly.
    obs->relativePoseIntensityWRTDepth =
        mrpt::obs::CObservation3DRangeScan().relativePoseIntensityWRTDepth;
    obs->sensorPose = toCPose3D(T_body_cam * mrptDepthFromOptical().inverse());
  } else {
    const Eigen::Isometry3d T_mrptdepth_color =
        mrptDepthFromOptical() * frame.T_color_depth.inverse();
    obs->relativePoseIntensityWRTDepth = toCPose3D(T_mrptdepth_color);
    obs->sensorPose = toCPose3D(T_body_cam * T_mrptdepth_color.inverse());
  }

  if (frame.hasDepth()) {
    if (frame.depth.type() != CV_16UC1)
      throw ConversionError(frame.source_label + ": depth image must be CV_16UC1");
    obs->hasRangeImage = true;
    obs->range_is_depth = true;
    obs->rangeUnits = static_cast<float>(frame.depth_unit_m);
    obs->rangeImage_setSize(frame.depth.rows, frame.depth.cols);
    for (int r = 0; r < frame.depth.rows; ++r) {
      const auto* row = frame.depth.ptr<std::uint16_t>(r);
      for (int c = 0; c < frame.depth.cols; ++c) obs->rangeImage(r, c) = row[c];
    }
  }
  if (frame.hasColor()) {
    if (frame.rgb.type() != CV_8UC3)
      throw ConversionError(frame.source_label + ": colour image must be CV_8UC3 (R,G,B)");
    cv::Mat bgr;
    cv::cvtColor(frame.rgb, bgr, cv::COLOR_RGB2BGR);
    obs->hasIntensityImage = true;
    obs->intensityImageChannel = mrpt::obs::CObservation3DRangeScan::CH_VISIBLE;
    obs->intensityImage = mrpt::img::CImage(bgr, mrpt::img::DEEP_COPY);
  }
  return obs;
}

ImuSample fromMrpt(const mrpt::obs::CObservationIMU& obs) {
  using namespace mrpt::obs;
  const TIMUDataIndex needed[] = {IMU_X_ACC, IMU_Y_ACC, IMU_Z_ACC, IMU_WX, IMU_WY, IMU_WZ};
  const char* names[] = {"IMU_X_ACC", "IMU_Y_ACC", "IMU_Z_ACC", "IMU_WX", "IMU_WY", "IMU_WZ"};
  const auto who = [&] {
    std::ostringstream os;
    os << std::fixed << std::setprecision(6);
    os << "IMU observation '" << obs.sensorLabel << "' at t = " << toSeconds(obs.timestamp) << " s";
    return os.str();
  };
  std::string missing;
  for (size_t i = 0; i < 6; ++i) {  // not obs.has(): see storedByte()
    const unsigned char present = storedByte(obs.dataIsPresent.at(needed[i]));
    if (present > 1) throwDamagedFlag(who() + ": the presence flag of " + names[i], present);
    if (present == 0) missing += (missing.empty() ? "" : " ") + std::string(names[i]);
  }
  if (!missing.empty())
    throw ConversionError(who() + " lacks accelerometer/gyroscope data: " + missing);
  ImuSample s;
  s.t = toSeconds(obs.timestamp);
  s.acc = Eigen::Vector3d(obs.get(IMU_X_ACC), obs.get(IMU_Y_ACC), obs.get(IMU_Z_ACC));
  s.gyr = Eigen::Vector3d(obs.get(IMU_WX), obs.get(IMU_WY), obs.get(IMU_WZ));
  return s;
}

mrpt::obs::CObservationIMU::Ptr toMrpt(const ImuSample& imu, const std::string& sensorLabel) {
  using namespace mrpt::obs;
  auto obs = CObservationIMU::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = fromSeconds(imu.t);
  obs->set(IMU_X_ACC, imu.acc.x());
  obs->set(IMU_Y_ACC, imu.acc.y());
  obs->set(IMU_Z_ACC, imu.acc.z());
  obs->set(IMU_WX, imu.gyr.x());
  obs->set(IMU_WY, imu.gyr.y());
  obs->set(IMU_WZ, imu.gyr.z());
  return obs;
}

WheelOdometrySample fromMrpt(const mrpt::obs::CObservationOdometry& obs) {
  const auto who = [&] {
    std::ostringstream os;
    os << std::fixed << std::setprecision(6);
    os << "odometry observation '" << obs.sensorLabel << "' at t = " << toSeconds(obs.timestamp)
       << " s";
    return os.str();
  };
  WheelOdometrySample w;
  w.t = toSeconds(obs.timestamp);
  w.x_m = obs.odometry.x();
  w.y_m = obs.odometry.y();
  w.yaw_rad = obs.odometry.phi();
  w.has_velocities = storedFlag(obs.hasVelocities, who() + ": hasVelocities");
  if (w.has_velocities) {
    w.v_forward_m_s = obs.velocityLocal.vx;
    w.v_lateral_m_s = obs.velocityLocal.vy;
    w.yaw_rate_rad_s = obs.velocityLocal.omega;
  }
  w.has_encoders = storedFlag(obs.hasEncodersInfo, who() + ": hasEncodersInfo");
  if (w.has_encoders) {
    w.ticks_left = obs.encoderLeftTicks;
    w.ticks_right = obs.encoderRightTicks;
  }
  return w;
}

mrpt::obs::CObservationOdometry::Ptr toMrpt(const WheelOdometrySample& wheel,
                                            const std::string& sensorLabel) {
  auto obs = mrpt::obs::CObservationOdometry::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = fromSeconds(wheel.t);
  obs->odometry = mrpt::poses::CPose2D(wheel.x_m, wheel.y_m, wheel.yaw_rad);
  obs->hasVelocities = wheel.has_velocities;
  if (wheel.has_velocities)
    obs->velocityLocal =
        mrpt::math::TTwist2D(wheel.v_forward_m_s, wheel.v_lateral_m_s, wheel.yaw_rate_rad_s);
  obs->hasEncodersInfo = wheel.has_encoders;
  if (wheel.has_encoders) {
    obs->encoderLeftTicks = wheel.ticks_left;
    obs->encoderRightTicks = wheel.ticks_right;
  }
  return obs;
}

}  // namespace rgbdi::io
