// Reader of an ASL dataset's sensor.yaml. Only what a recording needs is understood: top-level
// "key: value" scalars and the T_BS matrix, whose "data: [...]" list may span lines. Anything
// nested elsewhere (a camera's intrinsics list, ...) is skipped.
#include "asl_sensor_yaml.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <vector>

#include "rgbdi/sim/recording.h"

namespace rgbdi::sim {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

bool parseNumber(const std::string& text, double& v) {
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(v);
}

}  // namespace

double AslSensorYaml::number(const std::string& key) const {
  const auto it = values.find(key);
  if (it == values.end()) throw RecordingError(path + ": no '" + key + "'");
  double v = 0.0;
  if (!parseNumber(it->second, v))
    throw RecordingError(path + ": '" + key + "' value '" + it->second +
                         "' is not a finite number");
  return v;
}

AslSensorYaml readAslSensorYaml(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw RecordingError(path + ": cannot open (" + std::strerror(errno) + ")");
  AslSensorYaml y;
  y.path = path;
  std::string line, block;  // block: the top-level key whose nested lines are being read
  std::size_t n = 0, data_line = 0;
  std::string data;  // T_BS's list text while it is being collected
  bool collecting = false;
  auto fail = [&](std::size_t at, const std::string& what) {
    throw RecordingError(path + " line " + std::to_string(at) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++n;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    if (collecting) {
      data += " " + line;
      if (line.find(']') != std::string::npos) collecting = false;
      continue;
    }
    if (trim(line).empty() || trim(line) == "---" || trim(line).rfind('%', 0) == 0) continue;
    const bool nested = line[0] == ' ' || line[0] == '\t';
    const auto colon = line.find(':');
    if (colon == std::string::npos) {
      if (nested) continue;  // a list item of a block we do not read
      fail(n, "expected 'key: value'");
    }
    const std::string key = trim(line.substr(0, colon));
    const std::string value = trim(line.substr(colon + 1));
    if (!nested) {
      block = key;
      if (!value.empty()) y.values[key] = value;
      continue;
    }
    if (block == "T_BS" && key == "data") {
      data = value;
      data_line = n;
      collecting = value.find(']') == std::string::npos;
    }
  }
  if (collecting) fail(data_line, "T_BS data list not closed with ']'");
  if (data_line != 0) {
    const auto open = data.find('['), close = data.find(']');
    if (open == std::string::npos || close == std::string::npos || close < open)
      fail(data_line, "T_BS data is not a [ ... ] list");
    std::vector<double> v;
    std::string item;
    const std::string list = data.substr(open + 1, close - open - 1) + ",";
    for (char c : list) {
      if (c != ',') {
        item += c;
        continue;
      }
      double x = 0.0;
      if (!parseNumber(trim(item), x))
        fail(data_line, "T_BS value '" + trim(item) + "' is not a finite number");
      v.push_back(x);
      item.clear();
    }
    if (v.size() != 16)
      fail(data_line, "T_BS data has " + std::to_string(v.size()) + " values, expected 16");
    Eigen::Matrix4d T;
    for (int i = 0; i < 16; ++i) T(i / 4, i % 4) = v[static_cast<std::size_t>(i)];
    if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9)
      fail(data_line, "T_BS's last row is not 0 0 0 1");
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    if ((R * R.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-4 || R.determinant() < 0)
      fail(data_line, "T_BS's rotation is not a rotation (R R^T != I or det < 0)");
    y.T_BS = T;
  }
  return y;
}

}  // namespace rgbdi::sim
