#include "rgbdi/convert/vins_yaml.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/core.hpp>
#include <regex>
#include <sstream>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/ini_text.h"

namespace rgbdi::convert {
namespace {

/// Refuses text that is no YAML mapping of keys before OpenCV parses it (fuzzing finding 16:
/// OpenCV 4.6's YAML parser loops forever on "%YAML:1.0\n  t: f\n9, -\n", an indented key
/// followed by a line that is no key; finding 17: it also loops on block sequence items "- ..."
/// mixed into the keys). Every line outside a [...] or {...} flow collection must be blank, a
/// comment, a directive or document marker, "key: value" or "key:" (a VINS yaml has no block
/// sequences: its matrices hold their data in [...]); the text must hold no NUL byte; a
/// directive must be the YAML version (finding 18).
void checkYamlLines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  int depth = 0;  // open [ and { at the start of the line
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find('\0') != std::string::npos)
      throw ConfigError(path + " line " + std::to_string(number) + ": not a text file (NUL byte)");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t b = line.find_first_not_of(" \t");
    const std::string text = b == std::string::npos ? std::string() : line.substr(b);
    const auto refuse = [&](const std::string& why) {
      const std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
      throw ConfigError(path + " line " + std::to_string(number) + ": '" + shown + "' " + why);
    };
    if (depth == 0 && !text.empty() && text[0] == '%') {
      // Only the YAML version directive OpenCV writes, and none of its characters opens a flow
      // collection (finding 18: "%YAML:1.![:" opened one, and the lines after it went
      // unchecked into a parser loop).
      static const std::regex version(R"(%YAML[: ]1\.[0-9]+)");
      if (!std::regex_match(text, version)) refuse("is not a YAML version directive (%YAML:1.0)");
      continue;
    }
    if (depth == 0 && !text.empty() && text[0] != '#' && text != "---" && text != "...") {
      std::size_t k = 0;
      if (text[0] == '"' || text[0] == '\'') {
        k = text.find(text[0], 1);
        k = k == std::string::npos ? text.size() : k + 1;
      } else if (std::isalnum(static_cast<unsigned char>(text[0])) || text[0] == '_') {
        // A key starts with a letter, digit or '_' (finding 21: OpenCV looped on keys like
        // "---k2", which begin as a document marker).
        while (k < text.size() && (std::isalnum(static_cast<unsigned char>(text[k])) ||
                                   text[k] == '_' || text[k] == '-' || text[k] == '.'))
          ++k;
      }
      while (k < text.size() && text[k] == ' ') ++k;
      const bool key = k > 0 && k < text.size() && text[k] == ':' &&
                       (k + 1 == text.size() || text[k + 1] == ' ' || text[k + 1] == '\t');
      if (!key) refuse("is not 'key: value' (a VINS yaml is a mapping of keys)");
    }
    // Brackets of flow collections (outside quotes and comments) carry over to the next lines.
    char quote = 0;
    for (const char c : line) {
      if (quote) {
        if (c == quote) quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '#') {
        break;
      } else if (c == '[' || c == '{') {
        ++depth;
      } else if ((c == ']' || c == '}') && depth > 0) {
        --depth;
      }
    }
  }
}

class YamlReader {
 public:
  explicit YamlReader(const std::string& path) : path_(path) {
    if (!std::filesystem::is_regular_file(path)) throw ConfigError(path + ": no such file");
    checkYamlLines(path);
    try {
      fs_.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
    } catch (const cv::Exception& e) {
      throw ConfigError(path + ": not a readable OpenCV YAML file: " + e.err);
    } catch (const std::exception& e) {
      // OpenCV's parser also lets standard exceptions out of damaged text (fuzzing finding 5:
      // std::length_error from a string it sizes by a corrupt length).
      throw ConfigError(path + ": not a readable OpenCV YAML file: " + e.what());
    }
    if (!fs_.isOpened()) throw ConfigError(path + ": not a readable OpenCV YAML file");
    // Keys are looked up in the top-level node: OpenCV asserts (throws) when it is not a mapping
    // (fuzzing finding 6: a top-level sequence).
    if (!fs_.root().isMap())
      throw ConfigError(path + ": not a VINS yaml: the top level is not a mapping of keys");
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw ConfigError(path_ + " " + key + ": " + what);
  }

  cv::FileNode node(const std::string& key) const { return fs_[key]; }

  double number(const cv::FileNode& n, const std::string& key) const {
    if (n.empty() || n.isNone()) fail(key, "missing");
    if (!n.isReal() && !n.isInt()) fail(key, "not a number");
    const double v = static_cast<double>(n);
    if (!std::isfinite(v)) fail(key, "not a finite number");
    return v;
  }
  double number(const std::string& key) const { return number(fs_[key], key); }
  double positive(const std::string& key) const {
    const double v = number(key);
    if (!(v > 0.0)) fail(key, "must be positive");
    return v;
  }
  /// An image side in pixels: a whole number in the range rgbdi's [camera] accepts, checked
  /// before it becomes an int (fuzzing finding 7: a double beyond INT_MAX converted to int is
  /// undefined behaviour, UBSan; in practice INT_MIN, which later size products overflowed).
  int pixels(const std::string& key) const {
    const double v = number(key);
    if (v != std::floor(v) || v < kMinImageSide || v > kMaxImageSide) {
      std::ostringstream os;
      os << "must be a whole number of pixels from " << kMinImageSide << " to " << kMaxImageSide
         << ", got " << std::setprecision(17) << v;
      fail(key, os.str());
    }
    return static_cast<int>(v);
  }
  static constexpr int kMinImageSide = 16;    ///< [px] as [camera] width/height (sensor_options)
  static constexpr int kMaxImageSide = 8192;  ///< [px]
  cv::Mat matrix(const std::string& key, int rows, int cols) const {
    cv::Mat m;
    try {
      fs_[key] >> m;
    } catch (const cv::Exception& e) {
      fail(key, "not an opencv-matrix: " + e.err);
    } catch (const std::exception& e) {
      fail(key, std::string("not an opencv-matrix: ") + e.what());
    }
    if (m.empty()) fail(key, "missing or not an opencv-matrix");
    if (m.total() != static_cast<std::size_t>(rows * cols))
      fail(key, "expected a " + std::to_string(rows) + "x" + std::to_string(cols) +
                    " matrix, got " + std::to_string(m.rows) + "x" + std::to_string(m.cols));
    m.convertTo(m, CV_64F);
    return m.reshape(1, rows);
  }

 private:
  std::string path_;
  cv::FileStorage fs_;
};

/// [s] the largest rolling-shutter readout [camera] rolling_shutter_readout_s accepts.
constexpr double kMaxReadoutS = 1.0;

}  // namespace

VinsCalibration readVinsYaml(const std::string& path) {
  YamlReader y(path);
  VinsCalibration v;
  v.path = path;
  const cv::FileNode model = y.node("model_type");
  if (!model.empty() && model.isString() && static_cast<std::string>(model) != "PINHOLE")
    y.fail("model_type",
           "'" + static_cast<std::string>(model) + "' is not supported (only PINHOLE)");
  PinholeCamera& c = v.camera;
  c.width = y.pixels("image_width");
  c.height = y.pixels("image_height");
  const cv::FileNode proj = y.node("projection_parameters");
  if (proj.empty() || !proj.isMap()) y.fail("projection_parameters", "missing (fx, fy, cx, cy)");
  c.fx = y.number(proj["fx"], "projection_parameters.fx");
  c.fy = y.number(proj["fy"], "projection_parameters.fy");
  c.cx = y.number(proj["cx"], "projection_parameters.cx");
  c.cy = y.number(proj["cy"], "projection_parameters.cy");
  if (!(c.fx > 0.0) || !(c.fy > 0.0)) y.fail("projection_parameters", "fx and fy must be positive");
  const cv::FileNode dist = y.node("distortion_parameters");
  if (!dist.empty()) {
    if (!dist.isMap()) y.fail("distortion_parameters", "expected k1, k2, p1, p2");
    const char* names[] = {"k1", "k2", "p1", "p2"};
    for (int i = 0; i < 4; ++i)
      c.dist[static_cast<std::size_t>(i)] =
          y.number(dist[names[i]], std::string("distortion_parameters.") + names[i]);
  }
  const bool has_r = !y.node("extrinsicRotation").empty(),
             has_t = !y.node("extrinsicTranslation").empty();
  if (has_r != has_t)
    y.fail(has_r ? "extrinsicTranslation" : "extrinsicRotation", "missing (the other is given)");
  if (has_r) {
    const cv::Mat R = y.matrix("extrinsicRotation", 3, 3);
    const cv::Mat t = y.matrix("extrinsicTranslation", 3, 1);
    Eigen::Matrix3d Re;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Re(i, j) = R.at<double>(i, j);
    const double orth = (Re.transpose() * Re - Eigen::Matrix3d::Identity()).norm();
    if (orth > 1e-3 || Re.determinant() < 0.0) {
      std::ostringstream os;
      os << "not a rotation matrix (|R^T R - I| = " << orth << ", det = " << Re.determinant()
         << ")";
      y.fail("extrinsicRotation", os.str());
    }
    v.has_extrinsic = true;
    v.R_body_cam_as_given = Re;
    v.T_body_cam.linear() = Eigen::Quaterniond(Re).normalized().toRotationMatrix();
    v.T_body_cam.translation() = Eigen::Vector3d(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  }
  v.noise.acc_n = y.positive("acc_n");
  v.noise.gyr_n = y.positive("gyr_n");
  v.noise.acc_w = y.positive("acc_w");
  v.noise.gyr_w = y.positive("gyr_w");
  v.g_norm = y.positive("g_norm");
  if (!y.node("td").empty()) v.td = y.number("td");
  // VINS-Mono reads rolling_shutter_tr only when rolling_shutter is 1 (it is absent or ignored
  // for a global shutter); the readout must be one rgbdi's [camera] accepts.
  if (!y.node("rolling_shutter").empty()) {
    const double on = y.number("rolling_shutter");
    if (on != 0.0 && on != 1.0) y.fail("rolling_shutter", "must be 0 or 1");
    if (on == 1.0) {
      if (y.node("rolling_shutter_tr").empty())
        y.fail("rolling_shutter_tr", "missing (rolling_shutter is 1)");
      const double tr = y.number("rolling_shutter_tr");
      if (!(tr >= 0.0 && tr <= kMaxReadoutS))
        y.fail("rolling_shutter_tr", "must be a readout time from 0 to 1 s, got " + iniNumber(tr));
      v.rolling_shutter_readout_s = tr;
    }
  }
  return v;
}

ImuOptions imuOptionsFromVins(const VinsImuNoise& n, double g_norm, double rate_hz) {
  ImuOptions o;
  const double dt = 1.0 / rate_hz;
  o.rate_hz = rate_hz;
  o.acc_noise_density = n.acc_n * std::sqrt(dt / 2.0);
  o.gyr_noise_density = n.gyr_n * std::sqrt(dt / 2.0);
  o.acc_random_walk = n.acc_w * std::sqrt(dt);
  o.gyr_random_walk = n.gyr_w * std::sqrt(dt);
  o.gravity_m_s2 = g_norm;
  return o;
}

VinsImuNoise vinsNoiseFromImuOptions(const ImuOptions& imu) {
  const double dt = 1.0 / imu.rate_hz;
  VinsImuNoise n;
  n.acc_n = imu.acc_noise_density / std::sqrt(dt / 2.0);
  n.gyr_n = imu.gyr_noise_density / std::sqrt(dt / 2.0);
  n.acc_w = imu.acc_random_walk / std::sqrt(dt);
  n.gyr_w = imu.gyr_random_walk / std::sqrt(dt);
  return n;
}

std::string vinsYamlText(const PinholeCamera& camera, const Eigen::Isometry3d& T_body_cam,
                         const ImuOptions& imu, double td, double rolling_shutter_readout_s) {
  if (camera.dist[4] != 0.0)
    throw ConfigError("VINS calibration: the radial-tangential model has no k3 (k3 = " +
                      iniNumber(camera.dist[4]) + " cannot be written)");
  const VinsImuNoise n = vinsNoiseFromImuOptions(imu);
  const auto num = [](double x) { return iniNumber(x); };
  const Eigen::Matrix3d R = T_body_cam.rotation();
  const Eigen::Vector3d t = T_body_cam.translation();
  std::ostringstream os;
  os << "%YAML:1.0\n"
     << "# VINS-RGBD calibration of a sequence in the published dataset's layout.\n"
     << "imu_topic: \"/camera/imu\"\n"
     << "image_topic: \"/camera/color/image_raw\"\n"
     << "depth_topic: \"/camera/aligned_depth_to_color/image_raw\"\n"
     << "model_type: PINHOLE\n"
     << "camera_name: camera\n"
     << "image_width: " << camera.width << "\n"
     << "image_height: " << camera.height << "\n"
     << "distortion_parameters:\n"
     << "   k1: " << num(camera.dist[0]) << "\n"
     << "   k2: " << num(camera.dist[1]) << "\n"
     << "   p1: " << num(camera.dist[2]) << "\n"
     << "   p2: " << num(camera.dist[3]) << "\n"
     << "projection_parameters:\n"
     << "   fx: " << num(camera.fx) << "\n"
     << "   fy: " << num(camera.fy) << "\n"
     << "   cx: " << num(camera.cx) << "\n"
     << "   cy: " << num(camera.cy) << "\n"
     << "estimate_extrinsic: 0\n"
     << "extrinsicRotation: !!opencv-matrix\n"
     << "   rows: 3\n   cols: 3\n   dt: d\n   data: [";
  for (int i = 0; i < 9; ++i) os << (i ? ", " : "") << num(R(i / 3, i % 3));
  os << "]\n"
     << "extrinsicTranslation: !!opencv-matrix\n"
     << "   rows: 3\n   cols: 1\n   dt: d\n   data: [" << num(t.x()) << ", " << num(t.y()) << ", "
     << num(t.z()) << "]\n"
     << "acc_n: " << num(n.acc_n) << "\n"
     << "gyr_n: " << num(n.gyr_n) << "\n"
     << "acc_w: " << num(n.acc_w) << "\n"
     << "gyr_w: " << num(n.gyr_w) << "\n"
     << "g_norm: " << num(imu.gravity_m_s2) << "\n"
     << "estimate_td: 1\n"
     << "td: " << num(td) << "\n";
  if (rolling_shutter_readout_s != 0.0)
    os << "rolling_shutter: 1\n"
       << "rolling_shutter_tr: " << num(rolling_shutter_readout_s) << "\n";
  return os.str();
}

std::string rgbdiConfigFromVins(const VinsCalibration& v, double imu_rate_hz,
                                const std::string& rate_note) {
  const ImuOptions imu = imuOptionsFromVins(v.noise, v.g_norm, imu_rate_hz);
  const std::string name = std::filesystem::path(v.path).filename().string();
  std::ostringstream os;
  os << "; rgbdi configuration converted by rawlog-convert from the VINS calibration " << v.path
     << "\n"
     << "; Sections not given here take the defaults of share/config.ini.\n\n";
  const PinholeCamera& c = v.camera;
  os << "[camera]\n";
  iniLine(os, "width", std::to_string(c.width), "[px] image_width");
  iniLine(os, "height", std::to_string(c.height), "[px] image_height");
  iniLine(os, "fx", iniNumber(c.fx), "[px] projection_parameters");
  iniLine(os, "fy", iniNumber(c.fy), "[px]");
  iniLine(os, "cx", iniNumber(c.cx), "[px]");
  iniLine(os, "cy", iniNumber(c.cy), "[px]");
  iniLine(os, "distortion", iniDistortion(c),
          "k1 k2 p1 p2 k3 [unitless] distortion_parameters (VINS has no k3)");
  iniLine(os, "intrinsics_source", "config",
          "stream|config: use this calibration, not the one stored in the rawlog");
  iniLine(os, "rolling_shutter_readout_s", iniNumber(v.rolling_shutter_readout_s),
          v.rolling_shutter_readout_s != 0.0
              ? "[s] rolling_shutter_tr (rolling_shutter: 1)"
              : "[s] 0 = global shutter (rolling_shutter 0 or absent)");
  os << "\n[imu]\n";
  os << "; Densities from the VINS per-sample values at " << iniNumber(imu_rate_hz) << " Hz ("
     << rate_note << "): nd = n * sqrt(dt / 2), rw = w * sqrt(dt) (doc/imu.md).\n";
  iniLine(os, "rate_hz", iniNumber(imu_rate_hz), "[Hz]");
  iniLine(os, "acc_noise_density", iniNumber(imu.acc_noise_density),
          "[m/s^2/sqrt(Hz)]   (VINS acc_n " + iniNumber(v.noise.acc_n) + ")");
  iniLine(os, "gyr_noise_density", iniNumber(imu.gyr_noise_density),
          "[rad/s/sqrt(Hz)]   (VINS gyr_n " + iniNumber(v.noise.gyr_n) + ")");
  iniLine(os, "acc_random_walk", iniNumber(imu.acc_random_walk),
          "[m/s^3/sqrt(Hz)]   (VINS acc_w " + iniNumber(v.noise.acc_w) + ")");
  iniLine(os, "gyr_random_walk", iniNumber(imu.gyr_random_walk),
          "[rad/s^2/sqrt(Hz)] (VINS gyr_w " + iniNumber(v.noise.gyr_w) + ")");
  iniLine(os, "gravity_m_s2", iniNumber(v.g_norm), "[m/s^2] g_norm");
  os << "\n[extrinsic]\n";
  if (v.has_extrinsic) {
    std::string r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        r += (r.empty() ? "" : " ") + iniNumber(v.R_body_cam_as_given(i, j));
    iniLine(os, "R_body_cam", r,
            "row-major [unitless] extrinsicRotation (camera in the IMU frame)");
    const Eigen::Vector3d t = v.T_body_cam.translation();
    iniLine(os, "t_body_cam_m", iniNumber(t.x()) + " " + iniNumber(t.y()) + " " + iniNumber(t.z()),
            "[m] extrinsicTranslation");
  } else {
    os << "; " << name
       << " has no extrinsicRotation/extrinsicTranslation: the default extrinsic applies.\n";
  }
  iniLine(os, "time_offset_s", iniNumber(v.td), "[s] td: t_imu = t_cam + time_offset_s");
  const std::string text = os.str();

  // Load it back: what is written must be a configuration rgbdi-slam accepts.
  IniReader ini = IniReader::fromText(text, v.path + " (as rgbdi configuration)");
  CameraOptions::load(ini);
  ImuOptions::load(ini);
  ExtrinsicOptions::load(ini);
  ini.checkNoUnknownKeys();
  return text;
}

}  // namespace rgbdi::convert
