#include "rgbdi/bag/bag_converter.h"

#include <geometry_msgs/PoseStamped.h>
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Float32.h>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "rgbdi/bag/accel_gyro_merger.h"
#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/rgbd_pairer.h"
#include "rgbdi/bag/ros_calibration.h"
#include "rgbdi/bag/ros_image.h"
#include "rgbdi/bag/ros_odometry.h"
#include "rgbdi/bag/ros_wire.h"
#include "rgbdi/bag/wheel_extrinsic.h"
#include "rgbdi/common/sensor_options.h"

namespace rgbdi::bag {
namespace {

enum class Role { Color, Depth, Imu, Accel, Gyro, GroundTruth, Odometry };

/// A calibration that does not fit the images: ends the conversion (the output would be wrong).
class CalibrationMismatch : public BagError {
 public:
  using BagError::BagError;
};

template <typename M>
void deserialize(const std::uint8_t* data, std::uint32_t size, M& out) {
  ros::serialization::IStream s(const_cast<std::uint8_t*>(data), size);
  ros::serialization::deserialize(s, out);
}

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

std::string describeCamera(const PinholeCamera& c) {
  std::ostringstream os;
  os << c.width << "x" << c.height << ", fx " << fixed(c.fx, 3) << " fy " << fixed(c.fy, 3)
     << " cx " << fixed(c.cx, 3) << " cy " << fixed(c.cy, 3);
  if (c.hasDistortion())
    os << ", distortion " << c.dist[0] << " " << c.dist[1] << " " << c.dist[2] << " " << c.dist[3]
       << " " << c.dist[4];
  return os.str();
}

/// Two RealSense extrinsic topics ".../tf/<group>" of the same extrinsic group (comparable).
bool sameReference(const std::string& tf_a, const std::string& tf_b) {
  const auto group = [](const std::string& t) { return t.substr(t.rfind('/') + 1); };
  return group(tf_a) == group(tf_b);
}

}  // namespace

FallbackCalibration FallbackCalibration::defaults() {
  FallbackCalibration f;
  f.color = CameraOptions().camera;
  f.color_source = "built-in defaults (share/config.ini [camera])";
  f.T_body_cam = ExtrinsicOptions().T_body_cam;
  f.extrinsic_source = "built-in defaults (share/config.ini [extrinsic])";
  return f;
}

struct BagConverter::Impl {
  std::string path;
  ConvertOptions options;
  std::unique_ptr<BagReader> reader;
  BagLayout layout;
  std::map<std::string, Role> roles;
  PinholeCamera cam_color, cam_depth;
  double depth_unit = 1e-3;
  Eigen::Isometry3d T_color_depth = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Isometry3d> T_body_wheel;
  std::vector<std::string> calibration_lines, notes;
  bool ran = false;
  bool motion_only = false;

  // Per-run state.
  ConversionReport report;
  std::uint64_t frame_index = 0;
  bool checked_color_size = false, checked_depth_size = false;
  std::string color_source, depth_source;
  std::optional<double> last_odometry_t;  ///< stamp of the last odometry reading delivered

  template <typename M>
  bool firstMessage(const std::string& topic, M& msg) const {
    std::vector<std::uint8_t> bytes;
    if (topic.empty() || !reader->firstMessage(topic, bytes)) return false;
    try {
      deserialize(bytes.data(), static_cast<std::uint32_t>(bytes.size()), msg);
    } catch (const std::exception& e) {
      throw CalibrationError(path + " " + topic + ": unreadable first message: " + e.what());
    }
    return true;
  }

  void readCalibration(const FallbackCalibration& fallback) {
    sensor_msgs::CameraInfo info;
    if (firstMessage(layout.color_info, info)) {
      cam_color = cameraFromInfo(info, path + " " + layout.color_info);
      color_source = "camera_info " + layout.color_info;
    } else {
      cam_color = fallback.color;
      color_source = fallback.color_source;
    }
    calibration_lines.push_back("colour intrinsics: " + describeCamera(cam_color) + " (" +
                                color_source + ")");

    if (layout.depth_aligned) {
      cam_depth = cam_color;
      depth_source = color_source;
      calibration_lines.push_back("depth: aligned to the colour image (same intrinsics)");
    } else if (firstMessage(layout.depth_info, info)) {
      cam_depth = cameraFromInfo(info, path + " " + layout.depth_info);
      depth_source = "camera_info " + layout.depth_info;
      calibration_lines.push_back("depth intrinsics: " + describeCamera(cam_depth) + " (" +
                                  depth_source + ")");
    } else {
      cam_depth = cam_color;
      depth_source = color_source;
      calibration_lines.push_back(
          "depth intrinsics: none in the bag; the colour intrinsics are used");
    }

    std_msgs::Float32 units;
    if (firstMessage(layout.depth_units, units)) {
      if (!(units.data > 0.0f) || !(units.data < 1.0f))
        throw CalibrationError(path + " " + layout.depth_units + ": depth unit " +
                               std::to_string(units.data) + " m is not plausible");
      // The option is a float: 0.001f read back as the decimal it was meant to be.
      depth_unit = std::stod(fixed(static_cast<double>(units.data), 9));
      calibration_lines.push_back("depth unit: " + fixed(depth_unit * 1e3, 6) +
                                  " mm for 16-bit depth (" + layout.depth_units + ")");
    } else {
      depth_unit = options.integer_depth_unit_m;
      calibration_lines.push_back("depth unit: " + fixed(depth_unit * 1e3, 6) +
                                  " mm for 16-bit depth (default; the bag does not say)");
    }

    // The SDK writes each stream's "<stream>/tf/<group>" as the extrinsic from the group's
    // reference stream to that stream (librealsense ros_writer::write_extrinsics stores
    // get_extrinsics(stream) = the pin stream -> stream): p_stream = R p_ref + t, T_stream_ref.
    // The reference is the depth stream on D4xx cameras, but only the group has to be common.
    geometry_msgs::Transform tf;
    Eigen::Isometry3d T_color_ref = Eigen::Isometry3d::Identity(),
                      T_depth_ref = Eigen::Isometry3d::Identity();
    const bool have_color_tf = firstMessage(layout.color_tf, tf);
    if (have_color_tf) T_color_ref = isometryFromTransform(tf, path + " " + layout.color_tf);
    const bool have_depth_tf = firstMessage(layout.depth_tf, tf);
    if (have_depth_tf) T_depth_ref = isometryFromTransform(tf, path + " " + layout.depth_tf);
    if (!layout.depth_aligned) {
      if (have_color_tf && have_depth_tf && !sameReference(layout.color_tf, layout.depth_tf)) {
        calibration_lines.push_back("depth camera in the colour camera: unknown (" +
                                    layout.color_tf + " and " + layout.depth_tf +
                                    " have different references); identity used");
      } else if (have_color_tf) {
        // Without a depth tf the depth stream is taken as the reference (its tf is the identity).
        T_color_depth = T_color_ref * T_depth_ref.inverse();
        calibration_lines.push_back("depth camera in the colour camera (T_color_depth): " +
                                    describePose(T_color_depth) + " (" + layout.color_tf + ")");
      } else {
        calibration_lines.push_back(
            "depth camera in the colour camera: unknown (no extrinsics in the bag); identity used");
      }
    }

    const bool has_imu = !layout.imu.empty() || !layout.accel.empty();
    const bool have_imu_tf = has_imu && have_color_tf && firstMessage(layout.imu_tf, tf);
    if (have_imu_tf && sameReference(layout.imu_tf, layout.color_tf)) {
      const Eigen::Isometry3d T_imu_ref = isometryFromTransform(tf, path + " " + layout.imu_tf);
      T_body_cam = T_imu_ref * T_color_ref.inverse();  // T_imu_color: rgbdi's body is the IMU
      calibration_lines.push_back(
          "colour camera in the IMU (body) frame (T_body_cam): " + describePose(T_body_cam) + " (" +
          layout.imu_tf + ", " + layout.color_tf + ")");
    } else {
      T_body_cam = fallback.T_body_cam;
      calibration_lines.push_back("colour camera in the body frame (sensorPose): " +
                                  describePose(T_body_cam) + " (" + fallback.extrinsic_source +
                                  (have_imu_tf ? "; " + layout.imu_tf + " and " + layout.color_tf +
                                                     " have different references"
                                               : std::string()) +
                                  ")");
    }
  }

  std::string label(const BagMessage& m, double stamp) const {
    return path + " " + *m.topic + " message " + std::to_string(m.ordinal) + " (stamp " +
           fixed(stamp, 6) + " s)";
  }

  void checkSize(const cv::Mat& img, const PinholeCamera& cam, const std::string& what,
                 const std::string& source, const std::string& where, bool& checked) {
    if (checked) return;
    checked = true;
    if (img.cols != cam.width || img.rows != cam.height) {
      throw CalibrationMismatch(where + ": " + what + " images are " + std::to_string(img.cols) +
                                "x" + std::to_string(img.rows) + " but the intrinsics (" + source +
                                ") are for " + std::to_string(cam.width) + "x" +
                                std::to_string(cam.height) +
                                "; give this camera's calibration with --config or --camera-yaml");
    }
  }

  void deliverFrames(RgbdPairer& pairer, ConversionSink& sink) {
    PairedImages p;
    while (pairer.pop(p)) {
      auto f = frameFromPair(std::move(p), options.require_colour, &report.depth_alone_dropped);
      if (!f) continue;
      f->index = frame_index++;
      f->cam_color = cam_color;
      f->cam_depth = cam_depth;
      f->T_color_depth = T_color_depth;
      f->depth_aligned_to_color = layout.depth_aligned;
      sink.frame(*f);
    }
  }

  void deliverImu(AccelGyroMerger& merger, ConversionSink& sink) {
    ImuSample s;
    while (merger.pop(s)) sink.imu(s);
  }

  /// Handles one message; unreadable messages are reported and skipped.
  void handle(const BagMessage& m, Role role, RgbdPairer& pairer, AccelGyroMerger& merger,
              ConversionSink& sink) {
    const auto stampOf = [&](const std_msgs::Header& h) {
      if (h.stamp.isZero()) {
        ++report.stamps_from_bag_time;
        return m.bag_time;
      }
      return h.stamp.toSec();
    };
    std::string where = path + " " + *m.topic + " message " + std::to_string(m.ordinal);
    try {
      switch (role) {
        case Role::Color:
        case Role::Depth: {
          StampedImage img;
          const bool compressed =
              role == Role::Color ? layout.color_compressed : layout.depth_compressed;
          // Same steps for sensor_msgs/Image and sensor_msgs/CompressedImage (the decoders are
          // overloaded on the message type).
          auto decode = [&](auto&& msg) {
            deserializeImage(m.data, m.size, msg, where);  // lengths checked before allocating
            img.t = stampOf(msg.header);
            img.label = where = label(m, img.t);
            if (role == Role::Color) {
              img.image = decodeColorImage(msg, where);
            } else {
              DepthImage d = decodeDepthImage(msg, depth_unit, options.float_depth_unit_m, where);
              img.image = d.depth;
              img.unit_m = d.unit_m;
              report.depth_clipped_pixels += d.clipped;
            }
          };
          if (compressed) {
            decode(sensor_msgs::CompressedImage());
          } else {
            decode(sensor_msgs::Image());
          }
          if (role == Role::Color) {
            checkSize(img.image, cam_color, "colour", color_source, where, checked_color_size);
            ++report.color_images;
            pairer.pushColor(std::move(img));
          } else {
            checkSize(img.image, cam_depth, "depth", depth_source, where, checked_depth_size);
            ++report.depth_images;
            pairer.pushDepth(std::move(img));
          }
          deliverFrames(pairer, sink);
          break;
        }
        case Role::Imu: {
          sensor_msgs::Imu msg;
          deserialize(m.data, m.size, msg);
          ImuSample s;
          s.t = stampOf(msg.header);
          s.acc = Eigen::Vector3d(msg.linear_acceleration.x, msg.linear_acceleration.y,
                                  msg.linear_acceleration.z);
          s.gyr = Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y,
                                  msg.angular_velocity.z);
          ++report.imu_messages;
          sink.imu(s);
          break;
        }
        case Role::Accel:
        case Role::Gyro: {
          sensor_msgs::Imu msg;
          deserialize(m.data, m.size, msg);
          const double t = stampOf(msg.header);
          if (role == Role::Accel)
            merger.pushAccel(t,
                             Eigen::Vector3d(msg.linear_acceleration.x, msg.linear_acceleration.y,
                                             msg.linear_acceleration.z));
          else
            merger.pushGyro(t, Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y,
                                               msg.angular_velocity.z));
          deliverImu(merger, sink);
          break;
        }
        case Role::Odometry: {
          const nav_msgs::Odometry msg = deserializeOdometry(m.data, m.size, where);
          const double t = stampOf(msg.header);
          where = label(m, t);
          const WheelOdometrySample w = wheelFromOdometry(msg, t, where);
          // The readings are cumulative: one out of order cannot be placed; refuse it, named.
          if (last_odometry_t && !(t > *last_odometry_t)) {
            ++report.unreadable;
            report.addIssue("unreadable",
                            where + ": odometry stamp not after the previous reading's (" +
                                fixed(*last_odometry_t, 6) + " s); skipped",
                            options.max_listed_issues);
            break;
          }
          last_odometry_t = t;
          ++report.odometry_messages;
          sink.wheel(w);
          break;
        }
        case Role::GroundTruth: {
          geometry_msgs::PoseStamped msg;
          deserialize(m.data, m.size, msg);
          StampedPose p;
          p.t = stampOf(msg.header);
          p.p = Eigen::Vector3d(msg.pose.position.x, msg.pose.position.y, msg.pose.position.z);
          p.q = Eigen::Quaterniond(msg.pose.orientation.w, msg.pose.orientation.x,
                                   msg.pose.orientation.y, msg.pose.orientation.z);
          if (!(p.q.norm() > 1e-6) || !p.p.allFinite() || !p.q.coeffs().allFinite()) {
            ++report.unreadable;
            report.addIssue("unreadable",
                            where + ": invalid pose (zero or non-finite quaternion/position)",
                            options.max_listed_issues);
            break;
          }
          p.q.normalize();
          ++report.groundtruth_poses;
          sink.groundTruth(p);
          break;
        }
      }
    } catch (const ImageDecodeError& e) {
      ++report.unreadable;
      report.addIssue("unreadable", e.what(), options.max_listed_issues);
    } catch (const MessageDecodeError& e) {
      ++report.unreadable;
      report.addIssue("unreadable", e.what(), options.max_listed_issues);
    } catch (const ros::Exception& e) {
      // Message bytes that do not deserialise (e.g. a damaged record in an uncompressed chunk).
      ++report.unreadable;
      report.addIssue("unreadable", where + ": cannot deserialise: " + e.what(),
                      options.max_listed_issues);
    }
  }
};

BagConverter::BagConverter(const std::string& path, const ConvertOptions& options,
                           const BagInputOptions& input, const FallbackCalibration& fallback)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.path = path;
  d.options = options;
  d.motion_only = input.motion_only;
  d.reader = std::make_unique<BagReader>(path);
  try {
    d.layout = resolveBagLayout(d.reader->topics(), input.topics, input.depth_aligned, path);
  } catch (const BagLayoutError& e) {
    // A damaged bag shows only the topics of its readable part: say it is damaged first, as
    // --info does, rather than only that a topic is missing.
    if (d.reader->indexed()) throw;
    std::string what = e.what();
    if (what.rfind(path + ": ", 0) == 0) what = what.substr(path.size() + 2);
    const std::string damage =
        d.reader->damage().empty() ? std::string() : "; " + d.reader->damage();
    throw BagLayoutError(path + ": damaged bag: " + d.reader->recoveryReason() + damage +
                         "; in the readable part: " + what);
  }
  d.roles[d.layout.color] = Role::Color;
  d.roles[d.layout.depth] = Role::Depth;
  d.roles[d.layout.imu] = Role::Imu;
  d.roles[d.layout.accel] = Role::Accel;
  d.roles[d.layout.gyro] = Role::Gyro;
  d.roles[d.layout.groundtruth] = Role::GroundTruth;
  d.roles[d.layout.odometry] = Role::Odometry;
  d.roles.erase("");
  if (d.roles.size() != d.layout.streamedTopics().size())
    throw BagLayoutError(path + ": one topic is given for two different streams");
  d.readCalibration(fallback);
  BagWheelExtrinsic wheel = readWheelExtrinsic(*d.reader, d.layout, path);
  d.T_body_wheel = wheel.T_body_wheel;
  d.calibration_lines.insert(d.calibration_lines.end(), wheel.lines.begin(), wheel.lines.end());
}

BagConverter::~BagConverter() = default;

const BagLayout& BagConverter::layout() const { return impl_->layout; }
const Eigen::Isometry3d& BagConverter::T_body_cam() const { return impl_->T_body_cam; }
const PinholeCamera& BagConverter::colorCamera() const { return impl_->cam_color; }
const PinholeCamera& BagConverter::depthCamera() const { return impl_->cam_depth; }
double BagConverter::depthUnit() const { return impl_->depth_unit; }
const Eigen::Isometry3d& BagConverter::T_color_depth() const { return impl_->T_color_depth; }
const std::vector<std::string>& BagConverter::calibration() const {
  return impl_->calibration_lines;
}
const BagReader& BagConverter::reader() const { return *impl_->reader; }
const std::optional<Eigen::Isometry3d>& BagConverter::T_body_wheel() const {
  return impl_->T_body_wheel;
}

ConversionReport BagConverter::run(ConversionSink& sink, const ProgressCallback& progress,
                                   const std::atomic<bool>* stop) {
  Impl& d = *impl_;
  if (d.ran) throw BagError(d.path + ": BagConverter::run() called twice");
  d.ran = true;
  const auto start = std::chrono::steady_clock::now();
  ConversionReport& r = d.report;
  r.input = d.path;
  r.format = "ROS1 bag, " + toString(d.layout.kind);
  r.input_bytes = d.reader->fileSize();
  r.pair_tolerance_s = d.options.pair_tolerance_s;
  r.calibration = d.calibration_lines;
  for (const BagTopic& t : d.reader->topics()) {
    const auto it = d.roles.find(t.topic);
    if (it == d.roles.end()) continue;
    static const char* names[] = {"colour",    "depth",        "IMU",           "accelerometer",
                                  "gyroscope", "ground truth", "wheel odometry"};
    r.streams.push_back(std::string(names[static_cast<int>(it->second)]) + ": " + t.topic + " (" +
                        t.datatype + ", " + std::to_string(t.messages) + " messages)");
  }
  r.notes = d.layout.notes;
  if (!d.reader->indexed()) r.notes.push_back(d.reader->recoveryReason());

  RgbdPairer pairer(d.options.pair_tolerance_s, d.options.max_wait_s);
  AccelGyroMerger merger(d.options.max_accel_gap_s, d.options.max_wait_s);
  std::vector<std::string> topics = d.layout.streamedTopics();
  if (d.motion_only) {
    topics.clear();
    for (const std::string* t :
         {&d.layout.imu, &d.layout.accel, &d.layout.gyro, &d.layout.odometry})
      if (!t->empty()) topics.push_back(*t);
  }
  // Nothing selected would select everything: a motion-only run of a bag without motion
  // streams reads nothing.
  const bool nothing_to_read = topics.empty();
  d.reader->select(topics);
  BagMessage m;
  bool calibration_failed = false;
  try {
    while (!nothing_to_read && !(stop && stop->load())) {
      if (!d.reader->next(m)) break;
      d.handle(m, d.roles.at(*m.topic), pairer, merger, sink);
      if (progress) progress(d.reader->fraction());
    }
    if (stop && stop->load())
      r.notes.push_back("interrupted: the conversion stopped before the end of the bag");
  } catch (const BagReadError& e) {
    r.error = e.what();
  } catch (const CalibrationMismatch& e) {
    // Nothing more is written: frames with the wrong intrinsics would mislead every user.
    r.error = e.what();
    calibration_failed = true;
  }
  if (r.error.empty() && !d.reader->indexed())
    r.error = d.path + ": " + d.reader->recoveryReason() +
              "; every chunk up to the end of the file was read";
  pairer.finish();
  merger.finish();
  if (!calibration_failed) {
    d.deliverFrames(pairer, sink);
    d.deliverImu(merger, sink);
  }
  r.pairing = pairer.stats();
  r.merge = merger.stats();
  if (progress) progress(1.0);
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace rgbdi::bag
