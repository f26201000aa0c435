#include "live/sensor_keys.h"

#include <mrpt/config/CConfigFile.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace rgbdi::live {

SensorKeys::SensorKeys(const mrpt::config::CConfigFileBase& cfg, std::string section)
    : cfg_(cfg), section_(std::move(section)) {
  if (auto* f = dynamic_cast<const mrpt::config::CConfigFile*>(&cfg)) {
    file_ = f->getAssociatedFile();
    dir_ = std::filesystem::path(file_).parent_path().string();
  } else {
    file_ = "<sensors>";
  }
}

bool SensorKeys::has(const std::string& key) const { return cfg_.keyExists(section_, key); }

std::string SensorKeys::where(const std::string& key) const {
  return file_ + " [" + section_ + "] " + key;
}

void SensorKeys::fail(const std::string& key, const std::string& what) const {
  throw ConfigError(where(key) + ": " + what);
}

std::string SensorKeys::getString(const std::string& key, const std::string& def) const {
  std::string v = cfg_.read_string(section_, key, def);
  // A trailing "; comment" or "# comment" (the unit notes of rgbdi's INI files) is not part of
  // the value, as for IniReader.
  const auto c = v.find_first_of(";#");
  if (c != std::string::npos) v.resize(c);
  const auto b = v.find_first_not_of(" \t\r");
  const auto e = v.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : v.substr(b, e - b + 1);
}

double SensorKeys::getDouble(const std::string& key, double def, double min, double max) const {
  if (!has(key)) return def;
  const std::string s = getString(key, "");
  std::istringstream is(s);
  double v = 0.0;
  std::string rest;
  if (!(is >> v) || (is >> rest) || !std::isfinite(v)) fail(key, "'" + s + "' is not a number");
  if (v < min || v > max) {
    std::ostringstream os;
    os << s << " is out of range [" << min << ", " << max << "]";
    fail(key, os.str());
  }
  return v;
}

int SensorKeys::getInt(const std::string& key, int def, int min, int max) const {
  const double v = getDouble(key, def, min, max);
  if (v != std::floor(v)) fail(key, "'" + getString(key, "") + "' is not an integer");
  return static_cast<int>(v);
}

bool SensorKeys::getBool(const std::string& key, bool def) const {
  if (!has(key)) return def;
  std::string s = getString(key, "");
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  if (s == "true" || s == "1" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "0" || s == "no" || s == "off") return false;
  fail(key, "'" + s + "' is not a boolean (true/false)");
}

std::string SensorKeys::getEnum(const std::string& key, const std::string& def,
                                const std::vector<std::string>& allowed) const {
  const std::string s = getString(key, def);
  if (std::find(allowed.begin(), allowed.end(), s) != allowed.end()) return s;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : "|") + a;
  fail(key, "'" + s + "' is not one of " + list);
}

std::string SensorKeys::getPath(const std::string& key, bool required) const {
  const std::string s = getString(key, "");
  if (s.empty()) {
    if (required) fail(key, "missing (a file path is required)");
    return s;
  }
  const std::filesystem::path p(s);
  if (p.is_absolute() || dir_.empty()) return s;
  return (std::filesystem::path(dir_) / p).string();
}

}  // namespace rgbdi::live
