#include "rgbdi/live/sensor_config.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace rgbdi::live {
namespace {

const char* const kGlobal = "global";
/// [global] keys of MRPT's rawlog-grabber: allowed in the same file, not used by LiveSource.
const char* const kGrabberKeys[] = {"rawlog_prefix",     "time_between_launches",
                                    "SF_max_time_span",  "use_sensoryframes",
                                    "GRABBER_PERIOD_MS", "rawlog_GZ_compress_level"};

/// Section names in file order (IniReader exposes keys, not the section list).
std::vector<std::string> sectionsOf(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream is(text);
  std::string line;
  while (std::getline(is, line)) {
    const auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos || line[b] != '[') continue;
    const auto e = line.find(']', b);
    if (e == std::string::npos) continue;
    std::string name = line.substr(b + 1, e - b - 1);
    const auto nb = name.find_first_not_of(" \t");
    const auto ne = name.find_last_not_of(" \t");
    name = nb == std::string::npos ? std::string() : name.substr(nb, ne - nb + 1);
    bool seen = false;
    for (const auto& s : out) seen = seen || s == name;
    if (!seen && !name.empty()) out.push_back(name);
  }
  return out;
}

std::string readAll(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw ConfigError(path + ": cannot open the sensors file");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

LiveOptions LiveOptions::load(IniReader& ini) {
  LiveOptions o;
  o.image_queue_len = ini.getInt(kGlobal, "live_image_queue_len", o.image_queue_len, 1, 1000);
  o.imu_queue_len = ini.getInt(kGlobal, "live_imu_queue_len", o.imu_queue_len, 10, 10000000);
  o.camera_timeout_s =
      ini.getDouble(kGlobal, "live_camera_timeout_s", o.camera_timeout_s, 0.01, 3600.0);
  o.first_frame_timeout_s =
      ini.getDouble(kGlobal, "live_first_frame_timeout_s", o.first_frame_timeout_s, 0.01, 3600.0);
  o.imu_stall_s = ini.getDouble(kGlobal, "live_imu_stall_s", o.imu_stall_s, 0.001, 3600.0);
  o.imu_time_jump_s =
      ini.getDouble(kGlobal, "live_imu_time_jump_s", o.imu_time_jump_s, 1e-4, 3600.0);
  o.watchdog_period_s =
      ini.getDouble(kGlobal, "live_watchdog_period_s", o.watchdog_period_s, 1e-4, 1.0);
  o.max_listed_events =
      ini.getInt(kGlobal, "live_max_listed_events", o.max_listed_events, 0, 100000);
  return o;
}

SensorConfig SensorConfig::fromFile(const std::string& path) {
  // The text is parsed (not IniReader::fromFile) because the section list comes from it.
  SensorConfig c = fromText(readAll(path), path);
  c.path = path;
  return c;
}

SensorConfig SensorConfig::fromText(const std::string& text, const std::string& label) {
  IniReader ini = IniReader::fromText(text, label);
  SensorConfig c;
  c.text = text;
  c.live = LiveOptions::load(ini);
  for (const char* k : kGrabberKeys) ini.getString(kGlobal, k, "");
  for (const std::string& s : sectionsOf(text)) {
    if (s == kGlobal) continue;
    ini.acceptSection(s);
    if (ini.getBool(s, "rawlog-grabber-ignore", false)) continue;
    SensorSection sec;
    sec.name = s;
    sec.driver = ini.getString(s, "driver", "");
    if (sec.driver.empty())
      ini.fail(s, "driver", "missing: every sensor section names its CGenericSensor class");
    if (!ini.hasKey(s, "process_rate"))
      ini.fail(s, "process_rate", "missing: the rate [Hz] at which the sensor's thread runs");
    sec.process_rate_hz = ini.getDouble(s, "process_rate", 0.0, 1e-3, 100000.0);
    c.sensors.push_back(sec);
  }
  if (c.sensors.empty())
    throw ConfigError(label +
                      ": no sensor section (every section but [global] is one sensor, "
                      "with driver = CLASSNAME and process_rate = HZ)");
  ini.checkNoUnknownKeys();
  return c;
}

}  // namespace rgbdi::live
