// Reader of EuRoC MAV recordings (ASL CSV): the IMU and the ground truth of its body frame.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "asl_sensor_yaml.h"
#include "rgbdi/sim/recording.h"

namespace rgbdi::sim {
namespace {

namespace fs = std::filesystem;

// The ADIS16448 of the EuRoC MAV as the dataset's imu0/sensor.yaml gives it.
RecordedImuSensor eurocSensor() {
  RecordedImuSensor s;
  s.name = "ADIS16448 (EuRoC MAV imu0/sensor.yaml)";
  s.rate_hz = 200.0;
  s.gyr_noise_density = 1.6968e-4;
  s.gyr_random_walk = 1.9393e-5;
  s.acc_noise_density = 2.0e-3;
  s.acc_random_walk = 3.0e-3;
  s.gravity_m_s2 = 9.81;
  return s;
}

// cam0 in the body (IMU) frame, T_BS of the dataset's cam0/sensor.yaml.
Eigen::Isometry3d eurocCam0() {
  Eigen::Matrix4d m;
  m << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,  //
      0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,       //
      -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,   //
      0.0, 0.0, 0.0, 1.0;
  Eigen::Isometry3d T(m);
  // Given to 12 digits: the nearest rotation, so that the frame is exactly rigid.
  T.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  return T;
}

/// One CSV file read line by line, with the position for error messages.
class CsvLines {
 public:
  explicit CsvLines(std::string path) : path_(std::move(path)), in_(path_) {
    if (!in_) throw RecordingError(path_ + ": cannot open (" + std::strerror(errno) + ")");
  }

  /// The next data line split at commas (comments and blank lines skipped); false at the end.
  bool next(std::vector<std::string>& fields) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;
      fields.clear();
      std::size_t start = 0;
      while (true) {
        const auto comma = line.find(',', start);
        fields.push_back(trim(line.substr(start, comma - start)));
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      return true;
    }
    if (in_.bad()) fail("read error");
    return false;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw RecordingError(path_ + " line " + std::to_string(line_) + ": " + what);
  }

  long long stamp(const std::string& text) const {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE || v < 0)
      fail("timestamp '" + text + "' is not a non-negative integer of nanoseconds");
    return v;
  }

  double number(const std::string& text, const char* what) const {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
      fail(std::string(what) + " '" + text + "' is not a finite number");
    return v;
  }

  Eigen::Vector3d vector(const std::vector<std::string>& f, std::size_t first,
                         const char* what) const {
    return {number(f[first], what), number(f[first + 1], what), number(f[first + 2], what)};
  }

  const std::string& path() const { return path_; }

 private:
  static std::string trim(const std::string& s) {
    const auto a = s.find_first_not_of(" \t");
    if (a == std::string::npos) return {};
    return s.substr(a, s.find_last_not_of(" \t") - a + 1);
  }

  std::string path_;
  std::ifstream in_;
  std::size_t line_ = 0;
};

std::string firstExisting(const std::vector<fs::path>& candidates, const std::string& what,
                          const std::string& dir) {
  for (const fs::path& p : candidates)
    if (fs::is_regular_file(p)) return p.string();
  std::string list;
  for (const fs::path& p : candidates) list += (list.empty() ? "" : ", ") + p.string();
  throw RecordingError(dir + ": no EuRoC " + what + " file (looked for " + list + ")");
}

std::vector<ImuSample> readImu(const std::string& path) {
  CsvLines csv(path);
  std::vector<ImuSample> out;
  std::vector<std::string> f;
  long long last = -1;
  while (csv.next(f)) {
    if (f.size() != 7)
      csv.fail("expected 7 comma-separated values (t [ns], w xyz, a xyz), got " +
               std::to_string(f.size()));
    const long long ns = csv.stamp(f[0]);
    if (ns <= last)
      csv.fail("timestamp " + f[0] + " does not increase (previous " + std::to_string(last) + ")");
    last = ns;
    ImuSample s;
    s.t = nanosecondsToSeconds(ns);
    s.gyr = csv.vector(f, 1, "angular rate");
    s.acc = csv.vector(f, 4, "acceleration");
    out.push_back(s);
  }
  if (out.size() < 2) throw RecordingError(path + ": fewer than 2 IMU samples");
  return out;
}

std::vector<RecordedPose> readGroundTruth(const std::string& path) {
  CsvLines csv(path);
  std::vector<RecordedPose> out;
  std::vector<std::string> f;
  long long last = -1;
  while (csv.next(f)) {
    if (f.size() != 8 && f.size() != 11 && f.size() != 17)
      csv.fail("expected 8 (t, p xyz, q wxyz), 11 (+ v xyz) or 17 (+ bg, ba) values, got " +
               std::to_string(f.size()));
    const long long ns = csv.stamp(f[0]);
    if (ns <= last)
      csv.fail("timestamp " + f[0] + " does not increase (previous " + std::to_string(last) + ")");
    last = ns;
    RecordedPose g;
    g.t = nanosecondsToSeconds(ns);
    g.p_world = csv.vector(f, 1, "position");
    const Eigen::Vector4d q(csv.number(f[4], "quaternion w"), csv.number(f[5], "quaternion x"),
                            csv.number(f[6], "quaternion y"), csv.number(f[7], "quaternion z"));
    // A unit quaternion written to 6 digits has |q| within ~1e-5 of 1; anything far from it
    // is not a rotation.
    if (std::abs(q.norm() - 1.0) > 1e-3)
      csv.fail("quaternion (w x y z) has norm " + std::to_string(q.norm()) + ", not 1");
    g.q_world_body = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized();
    if (f.size() >= 11) {
      g.has_velocity = true;
      g.v_world = csv.vector(f, 8, "velocity");
    }
    if (f.size() == 17) {
      g.has_bias = true;
      g.bias.gyr = csv.vector(f, 11, "gyro bias");
      g.bias.acc = csv.vector(f, 14, "accelerometer bias");
    }
    out.push_back(g);
  }
  if (out.size() < 2) throw RecordingError(path + ": fewer than 2 ground-truth samples");
  return out;
}

// The IMU as its sensor.yaml describes it (rate and the four Kalibr noise values; the name from
// its comment). Body = IMU frame: an IMU T_BS other than the identity is refused.
RecordedImuSensor imuSensorFromYaml(const std::string& path) {
  const AslSensorYaml y = readAslSensorYaml(path);
  if (y.T_BS && (*y.T_BS - Eigen::Matrix4d::Identity()).norm() > 1e-9)
    throw RecordingError(path +
                         ": T_BS is not the identity; the ground truth must be of the "
                         "IMU's own frame (body = IMU)");
  RecordedImuSensor s;
  const auto comment = y.values.find("comment");
  s.name = (comment != y.values.end() ? comment->second + " " : std::string()) + "(" + path + ")";
  s.rate_hz = y.number("rate_hz");
  s.gyr_noise_density = y.number("gyroscope_noise_density");
  s.gyr_random_walk = y.number("gyroscope_random_walk");
  s.acc_noise_density = y.number("accelerometer_noise_density");
  s.acc_random_walk = y.number("accelerometer_random_walk");
  for (const double v :
       {s.rate_hz, s.gyr_noise_density, s.gyr_random_walk, s.acc_noise_density, s.acc_random_walk})
    if (!(v > 0.0)) throw RecordingError(path + ": rate and noise values must be positive");
  return s;
}

Eigen::Isometry3d cameraFromYaml(const std::string& path) {
  const AslSensorYaml y = readAslSensorYaml(path);
  if (!y.T_BS) throw RecordingError(path + ": no T_BS");
  Eigen::Isometry3d T(*y.T_BS);
  T.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  return T;
}

}  // namespace

Recording readEurocRecording(const std::string& dir) {
  if (!fs::is_directory(dir)) throw RecordingError(dir + ": not a directory");
  const fs::path d(dir);
  Recording r;
  r.format = "euroc";
  r.directory = dir;
  const fs::path imu_file = firstExisting(
      {d / "imu0.csv", d / "imu0" / "data.csv", d / "mav0" / "imu0" / "data.csv"}, "IMU", dir);
  r.imu = readImu(imu_file.string());
  r.ground_truth = readGroundTruth(
      firstExisting({d / "groundtruth.csv", d / "state_groundtruth_estimate0" / "data.csv",
                     d / "mav0" / "state_groundtruth_estimate0" / "data.csv"},
                    "ground-truth", dir));
  // The ASL layout describes its sensors next to their data; without (the flat layout, or a
  // copy without them) the EuRoC MAV's.
  const fs::path imu_yaml = imu_file.parent_path() / "sensor.yaml";
  const fs::path cam_yaml = imu_file.parent_path().parent_path() / "cam0" / "sensor.yaml";
  const bool asl = imu_file.filename() == "data.csv";
  r.sensor =
      asl && fs::is_regular_file(imu_yaml) ? imuSensorFromYaml(imu_yaml.string()) : eurocSensor();
  r.T_body_cam =
      asl && fs::is_regular_file(cam_yaml) ? cameraFromYaml(cam_yaml.string()) : eurocCam0();
  return r;
}

}  // namespace rgbdi::sim
