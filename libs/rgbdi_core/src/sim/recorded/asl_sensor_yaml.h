// The sensor.yaml of an ASL-layout dataset (EuRoC, TUM-VI and recordings converted to that
// layout): flat "key: value" lines and the 4 x 4 "T_BS" block (cols, rows, data: [...]).
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>

namespace rgbdi::sim {

struct AslSensorYaml {
  std::string path;
  std::map<std::string, std::string> values;  ///< top-level scalars, as written
  std::optional<Eigen::Matrix4d> T_BS;        ///< sensor in the body frame, row-major data

  /// The value of `key` as a finite number; RecordingError (file, key) when absent or not one.
  double number(const std::string& key) const;
};

/// Reads `path`; RecordingError naming the file, the line and the fault when malformed.
AslSensorYaml readAslSensorYaml(const std::string& path);

}  // namespace rgbdi::sim
