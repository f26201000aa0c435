// Validated reading of one sensor section from the MRPT config object a CGenericSensor gets in
// loadConfig_sensorSpecific (LiveSource or rawlog-grabber built it): every key with its default
// and range; bad values throw ConfigError naming file, section and key. Relative paths are taken
// relative to the INI file's directory (when the config comes from a file).
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::live {

class SensorKeys {
 public:
  SensorKeys(const mrpt::config::CConfigFileBase& cfg, std::string section);

  bool has(const std::string& key) const;
  std::string getString(const std::string& key, const std::string& def) const;
  double getDouble(const std::string& key, double def, double min, double max) const;
  int getInt(const std::string& key, int def, int min, int max) const;
  bool getBool(const std::string& key, bool def) const;
  std::string getEnum(const std::string& key, const std::string& def,
                      const std::vector<std::string>& allowed) const;
  /// A file path; "" when absent and not `required` (then ConfigError). Relative to the INI's
  /// directory.
  std::string getPath(const std::string& key, bool required) const;

  /// "FILE [section] key".
  std::string where(const std::string& key) const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  const std::string& section() const { return section_; }

 private:
  const mrpt::config::CConfigFileBase& cfg_;
  std::string section_, file_, dir_;
};

}  // namespace rgbdi::live
