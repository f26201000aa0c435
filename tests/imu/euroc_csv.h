// Test helper: readers for the EuRoC ASL csv files of ../shared/data/euroc_v102 (imu0.csv,
// groundtruth.csv). Stamps are integer nanoseconds; they are converted to seconds relative to a
// caller-given origin so that no precision is lost in doubles.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"

namespace rgbdi::test {

struct EurocState {
  double t = 0.0;
  Eigen::Vector3d p, v, bg, ba;
  Eigen::Quaterniond q;  // R_world_body
};

namespace detail {

// Calls fn(stamp_ns, values) for every data line; throws naming file and line on bad input.
template <typename Fn>
void forEachCsvRow(const std::string& path, std::size_t expected_values, Fn fn) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string field;
    std::vector<std::string> fields;
    while (std::getline(ss, field, ',')) fields.push_back(field);
    if (fields.size() != expected_values + 1)
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " +
                               std::to_string(expected_values + 1) + " fields, got " +
                               std::to_string(fields.size()));
    try {
      std::vector<double> values;
      for (std::size_t k = 1; k < fields.size(); ++k) values.push_back(std::stod(fields[k]));
      fn(static_cast<std::int64_t>(std::stoll(fields[0])), values);
    } catch (const std::logic_error&) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": not a number in '" + line +
                               "'");
    }
  }
}

}  // namespace detail

/// imu0.csv: t[ns], gyro xyz [rad/s], accel xyz [m/s^2].
inline std::vector<ImuSample> loadEurocImu(const std::string& path, std::int64_t origin_ns) {
  std::vector<ImuSample> out;
  detail::forEachCsvRow(path, 6, [&](std::int64_t ns, const std::vector<double>& v) {
    ImuSample s;
    s.t = static_cast<double>(ns - origin_ns) * 1e-9;
    s.gyr = Eigen::Vector3d(v[0], v[1], v[2]);
    s.acc = Eigen::Vector3d(v[3], v[4], v[5]);
    out.push_back(s);
  });
  return out;
}

/// groundtruth.csv: t[ns], p xyz, q wxyz, v xyz, gyro bias xyz, accel bias xyz.
inline std::vector<EurocState> loadEurocGroundTruth(const std::string& path,
                                                    std::int64_t origin_ns) {
  std::vector<EurocState> out;
  detail::forEachCsvRow(path, 16, [&](std::int64_t ns, const std::vector<double>& v) {
    EurocState s;
    s.t = static_cast<double>(ns - origin_ns) * 1e-9;
    s.p = Eigen::Vector3d(v[0], v[1], v[2]);
    s.q = Eigen::Quaterniond(v[3], v[4], v[5], v[6]).normalized();
    s.v = Eigen::Vector3d(v[7], v[8], v[9]);
    s.bg = Eigen::Vector3d(v[10], v[11], v[12]);
    s.ba = Eigen::Vector3d(v[13], v[14], v[15]);
    out.push_back(s);
  });
  return out;
}

struct EurocSequence {
  std::vector<ImuSample> imu;     ///< t [s] relative to the first IMU stamp
  std::vector<EurocState> truth;  ///< same time origin
};

/// Reads dir/imu0.csv and dir/groundtruth.csv with the first IMU stamp as time origin.
inline EurocSequence loadEurocSequence(const std::string& dir) {
  std::int64_t origin = -1;
  detail::forEachCsvRow(dir + "/imu0.csv", 6, [&](std::int64_t ns, const std::vector<double>&) {
    if (origin < 0) origin = ns;
  });
  if (origin < 0) throw std::runtime_error(dir + "/imu0.csv: no data line");
  EurocSequence seq;
  seq.imu = loadEurocImu(dir + "/imu0.csv", origin);
  seq.truth = loadEurocGroundTruth(dir + "/groundtruth.csv", origin);
  return seq;
}

}  // namespace rgbdi::test
