#include "rgbdi/convert/tum_rgbd.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "rgbdi/bag/rgbd_pairer.h"
#include "rgbdi/common/atomic_file.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;

/// Reads a whitespace-separated text file line by line; '#' starts a comment line.
class LineReader {
 public:
  LineReader(std::string path, bool required) : path_(std::move(path)) {
    if (!fs::exists(path_)) {
      if (required) throw IoError(path_ + ": no such file");
      return;
    }
    in_.open(path_);
    if (!in_) throw IoError(path_ + ": cannot open for reading");
  }
  bool exists() const { return in_.is_open(); }
  /// The next non-comment line split into fields; false at the end of the file.
  bool next(std::vector<std::string>& fields) {
    std::string line;
    while (in_.is_open() && std::getline(in_, line)) {
      ++line_no_;
      const auto first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#') continue;
      std::istringstream is(line);
      fields.clear();
      for (std::string f; is >> f;) fields.push_back(f);
      return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw IoError(path_ + " line " + std::to_string(line_no_) + ": " + what);
  }
  double number(const std::string& text, const char* what) const {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
      fail(std::string(what) + " '" + text + "' is not a number");
    return v;
  }
  double stamp(const std::string& text) const {
    const double t = number(text, "timestamp");
    if (!(t > 0.0)) fail("timestamp '" + text + "' is not positive");
    return t;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::ifstream in_;
  std::size_t line_no_ = 0;
};

/// The next accelerometer sample or ground-truth pose of a streamed list (NaN stamp at the end).
struct StreamedLists {
  LineReader accel, gt;
  double accel_t = std::numeric_limits<double>::quiet_NaN(),
         gt_t = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d acc;
  StampedPose pose;

  explicit StreamedLists(const std::string& folder)
      : accel((fs::path(folder) / "accelerometer.txt").string(), false),
        gt((fs::path(folder) / "groundtruth.txt").string(), false) {
    advanceAccel();
    advanceGt();
  }
  void advanceAccel() {
    std::vector<std::string> f;
    accel_t = std::numeric_limits<double>::quiet_NaN();
    if (!accel.next(f)) return;
    if (f.size() != 4)
      accel.fail("expected 'timestamp ax ay az', got " + std::to_string(f.size()) + " fields");
    accel_t = accel.stamp(f[0]);
    acc = Eigen::Vector3d(accel.number(f[1], "ax"), accel.number(f[2], "ay"),
                          accel.number(f[3], "az"));
  }
  void advanceGt() {
    std::vector<std::string> f;
    gt_t = std::numeric_limits<double>::quiet_NaN();
    if (!gt.next(f)) return;
    if (f.size() != 8)
      gt.fail("expected 'timestamp tx ty tz qx qy qz qw', got " + std::to_string(f.size()) +
              " fields");
    pose.t = gt_t = gt.stamp(f[0]);
    pose.p = Eigen::Vector3d(gt.number(f[1], "tx"), gt.number(f[2], "ty"), gt.number(f[3], "tz"));
    pose.q = Eigen::Quaterniond(gt.number(f[7], "qw"), gt.number(f[4], "qx"), gt.number(f[5], "qy"),
                                gt.number(f[6], "qz"));
    if (!(pose.q.norm() > 1e-6)) gt.fail("zero quaternion");
    pose.q.normalize();
  }
};

std::uint64_t sizeOf(const std::string& path) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  return ec ? 0 : n;
}

}  // namespace

PinholeCamera tumCamera(const std::string& name) {
  // The TUM RGB-D benchmark's published calibration of the colour cameras (640x480; fr3 images
  // are already undistorted) and ROS' default Kinect intrinsics.
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  if (name == "fr1") {
    c.fx = 517.3, c.fy = 516.5, c.cx = 318.6, c.cy = 255.3;
    c.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  } else if (name == "fr2") {
    c.fx = 520.9, c.fy = 521.0, c.cx = 325.1, c.cy = 249.7;
    c.dist = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172};
  } else if (name == "fr3") {
    c.fx = 535.4, c.fy = 539.2, c.cx = 320.1, c.cy = 247.6;
  } else if (name == "ros") {
    c.fx = 525.0, c.fy = 525.0, c.cx = 319.5, c.cy = 239.5;
  } else {
    throw std::invalid_argument("unknown TUM camera '" + name +
                                "' (valid: fr1, fr2, fr3, ros, config)");
  }
  return c;
}

std::string detectTumCamera(const std::string& folder) {
  std::string name = fs::path(folder).filename().string();
  if (name.empty()) name = fs::path(folder).parent_path().filename().string();
  for (const char* k : {"1", "2", "3"}) {
    if (name.find(std::string("freiburg") + k) != std::string::npos ||
        name.find(std::string("fr") + k) != std::string::npos)
      return std::string("fr") + k;
  }
  return "";
}

std::vector<TumImageEntry> readTumImageList(const std::string& path) {
  LineReader r(path, true);
  std::vector<TumImageEntry> list;
  std::vector<std::string> f;
  while (r.next(f)) {
    if (f.size() != 2)
      r.fail("expected 'timestamp filename', got " + std::to_string(f.size()) + " fields");
    list.push_back({r.stamp(f[0]), f[1]});
  }
  std::stable_sort(list.begin(), list.end(),
                   [](const TumImageEntry& a, const TumImageEntry& b) { return a.t < b.t; });
  return list;
}

TumRgbdConverter::TumRgbdConverter(const std::string& folder, const bag::ConvertOptions& options,
                                   const std::string& camera,
                                   const bag::FallbackCalibration& fallback)
    : folder_(folder), options_(options) {
  if (!fs::is_directory(folder)) throw IoError(folder + ": not a directory");
  rgb_ = readTumImageList((fs::path(folder) / "rgb.txt").string());
  depth_ = readTumImageList((fs::path(folder) / "depth.txt").string());
  for (const auto* list : {&rgb_, &depth_})
    for (const TumImageEntry& e : *list)
      total_bytes_ += sizeOf((fs::path(folder) / e.file).string());

  std::string name = camera;
  std::string how = "given with --tum-camera";
  if (name.empty()) {
    name = detectTumCamera(folder);
    how = "detected from the folder name";
    if (name.empty()) {
      if (!fallback.intrinsics_from_user)
        throw std::invalid_argument(
            folder +
            ": cannot tell the TUM camera from the folder name; give "
            "--tum-camera fr1|fr2|fr3|ros or the intrinsics with --config / --camera-yaml");
      name = "config";
    }
  }
  if (name == "config") {
    camera_ = fallback.color;
    calibration_.push_back("colour intrinsics: " + fallback.color_source);
  } else {
    camera_ = tumCamera(name);
    calibration_.push_back("colour intrinsics: TUM " + name + " calibration (" + how + ")");
  }
  calibration_.push_back("depth: registered to the colour image (same intrinsics), " +
                         std::to_string(options.tum_depth_factor) + " units per metre");
  if (fallback.extrinsic_from_user) {
    T_body_cam_ = fallback.T_body_cam;
    calibration_.push_back("colour camera in the body frame (sensorPose): " +
                           fallback.extrinsic_source);
  } else {
    calibration_.push_back(
        "colour camera in the body frame (sensorPose): identity (TUM has no IMU frame)");
  }
}

bag::ConversionReport TumRgbdConverter::run(bag::ConversionSink& sink,
                                            const bag::ProgressCallback& progress,
                                            const std::atomic<bool>* stop) {
  const auto start = std::chrono::steady_clock::now();
  bag::ConversionReport r;
  r.input = folder_;
  r.format = "TUM RGB-D folder";
  r.input_bytes = total_bytes_;
  r.pair_tolerance_s = options_.pair_tolerance_s;
  r.calibration = calibration_;
  r.streams.push_back("colour: rgb.txt (" + std::to_string(rgb_.size()) + " images)");
  r.streams.push_back("depth: depth.txt (" + std::to_string(depth_.size()) + " images)");

  StreamedLists lists(folder_);
  if (lists.accel.exists()) r.streams.push_back("accelerometer: accelerometer.txt");
  if (lists.gt.exists())
    r.streams.push_back("ground truth: groundtruth.txt (pose of the colour camera)");
  r.notes.push_back(
      "TUM RGB-D has no gyroscope: accelerometer.txt is written as acceleration-only "
      "CObservationIMU "
      "(rgbdi-slam needs a gyroscope and cannot use them)");
  if (!lists.gt.exists()) r.notes.push_back("no groundtruth.txt: no ground truth written");

  bag::RgbdPairer pairer(options_.pair_tolerance_s, options_.max_wait_s);
  const double depth_unit = 1.0 / options_.tum_depth_factor;
  std::uint64_t bytes_done = 0, frame_index = 0;
  bool size_checked = false, calibration_failed = false;

  const auto deliver = [&]() {
    bag::PairedImages p;
    while (pairer.pop(p)) {
      auto f = bag::frameFromPair(std::move(p), options_.require_colour, &r.depth_alone_dropped);
      if (!f) continue;
      f->index = frame_index++;
      f->cam_color = f->cam_depth = camera_;
      f->depth_aligned_to_color = true;
      sink.frame(*f);
    }
  };
  const auto loadImage = [&](const TumImageEntry& e, bool color) -> bool {
    const std::string path = (fs::path(folder_) / e.file).string();
    bytes_done += sizeOf(path);
    const std::string label = path + " (stamp " + std::to_string(e.t) + " s)";
    cv::Mat img = cv::imread(path, color ? cv::IMREAD_COLOR : cv::IMREAD_ANYDEPTH);
    if (img.empty() || (!color && img.type() != CV_16UC1)) {
      ++r.unreadable;
      r.addIssue(
          "unreadable",
          label + (img.empty() ? ": missing or unreadable image" : ": not a 16-bit depth PNG"),
          options_.max_listed_issues);
      return true;
    }
    if (!size_checked && (img.cols != camera_.width || img.rows != camera_.height)) {
      r.error = label + ": images are " + std::to_string(img.cols) + "x" +
                std::to_string(img.rows) + " but the intrinsics are for " +
                std::to_string(camera_.width) + "x" + std::to_string(camera_.height) +
                "; give this camera's calibration with --config or --camera-yaml";
      calibration_failed = true;
      return false;
    }
    size_checked = true;
    bag::StampedImage s;
    s.t = e.t;
    s.label = label;
    if (color) {
      cv::cvtColor(img, s.image, cv::COLOR_BGR2RGB);
      ++r.color_images;
      pairer.pushColor(std::move(s));
    } else {
      s.image = img;
      s.unit_m = depth_unit;
      ++r.depth_images;
      pairer.pushDepth(std::move(s));
    }
    deliver();
    return true;
  };

  std::size_t ic = 0, id = 0;
  const double inf = std::numeric_limits<double>::infinity();
  try {
    while (!(stop && stop->load())) {
      const double tc = ic < rgb_.size() ? rgb_[ic].t : inf;
      const double td = id < depth_.size() ? depth_[id].t : inf;
      const double ta = std::isnan(lists.accel_t) ? inf : lists.accel_t;
      const double tg = std::isnan(lists.gt_t) ? inf : lists.gt_t;
      const double t = std::min({tc, td, ta, tg});
      if (t == inf) break;
      if (ta == t) {
        sink.accelerometer(ta, lists.acc);
        ++r.accel_only_samples;
        lists.advanceAccel();
      } else if (tg == t) {
        ++r.groundtruth_poses;
        sink.groundTruth(lists.pose);
        lists.advanceGt();
      } else if (tc == t) {
        if (!loadImage(rgb_[ic++], true)) break;
      } else {
        if (!loadImage(depth_[id++], false)) break;
      }
      if (progress && total_bytes_ > 0)
        progress(std::min(1.0, static_cast<double>(bytes_done) / total_bytes_));
    }
  } catch (const IoError& e) {
    r.error = e.what();
  }
  if (stop && stop->load())
    r.notes.push_back("interrupted: the conversion stopped before the end of the folder");
  pairer.finish();
  if (!calibration_failed) deliver();  // frames with wrong intrinsics would mislead
  r.pairing = pairer.stats();
  if (progress) progress(1.0);
  r.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace rgbdi::convert
