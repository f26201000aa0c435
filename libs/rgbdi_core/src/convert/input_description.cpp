#include "rgbdi/convert/input_description.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/ros_calibration.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/convert/bag_wheel_check.h"
#include "rgbdi/convert/tum_rgbd.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

/// Stamps of the first column of a TUM list file (comments skipped); empty when the file is absent.
std::vector<double> listStamps(const std::string& path) {
  std::vector<double> t;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    t.push_back(std::strtod(line.c_str() + first, nullptr));
  }
  return t;
}

/// The wheel stream's checks (bag_wheel_check.h): the "Wheel:" block of a rawlog's --info and
/// the wheel checks' warnings.
void describeWheels(const std::string& path, const ConversionSettings& settings,
                    const bag::TopicOverrides& topics, const io::StreamConfig& stream,
                    const bag::BagLayout& l, std::ostream& os, json& j) {
  const io::StreamDiagnostics w = checkBagWheels(path, settings, topics, stream);
  const std::string imu = !l.imu.empty() ? l.imu : l.gyro;
  os << "Wheel odometry " << l.odometry << " checked against the IMU "
     << (imu.empty() ? "(none: no rest checks)" : imu) << ":\n";
  os << "Wheel: " << w.wheel.delivered << " readings, " << fixed(w.wheel.duration_s, 3) << " s, "
     << fixed(w.wheel.rate_hz, 2) << " Hz\n"
     << w.wheelReport();
  json jw = json::parse(w.toJson());
  j["wheel"] = jw.contains("wheel") ? jw["wheel"] : json::object();
  j["wheel"]["warnings"] = w.wheel_warnings;
  std::vector<std::string> lines = w.wheel_warnings;
  // Unreadable odometry or IMU messages are listed too (they are not in wheel_warnings).
  for (const std::string& m : w.warnings)
    if (m.find(" message ") != std::string::npos && m.find(path + " ") == 0) lines.push_back(m);
  if (!w.error.empty()) lines.push_back("error: " + w.error);
  os << "Wheel warnings: " << lines.size() << "\n";
  for (const std::string& m : lines) os << "  " << m << "\n";
}

}  // namespace

InputDescription describeBag(const std::string& path, const ConversionSettings& settings,
                             const bag::TopicOverrides& topics, const io::StreamConfig& stream) {
  InputDescription d;
  json j;
  std::ostringstream os;
  std::unique_ptr<bag::BagConverter> conv;
  std::string layout_error;
  try {
    conv = std::make_unique<bag::BagConverter>(
        path, settings.options, bag::BagInputOptions{topics, std::nullopt}, settings.calibration);
  } catch (const bag::BagLayoutError& e) {
    layout_error = e.what();
  } catch (const bag::CalibrationError& e) {
    layout_error = e.what();
  }
  // The reader alone when no conversion is possible.
  std::unique_ptr<bag::BagReader> own_reader;
  if (!conv) own_reader = std::make_unique<bag::BagReader>(path);
  const bag::BagReader& reader = conv ? conv->reader() : *own_reader;

  const double duration = reader.endTime() - reader.beginTime();
  std::uint64_t total = 0;
  for (const bag::BagTopic& t : reader.topics()) total += t.messages;
  os << "ROS1 bag: " << path << " (" << fixed(static_cast<double>(reader.fileSize()) / 1e6, 1)
     << " MB, " << (reader.indexed() ? "indexed" : "index unreadable") << ")\n";
  if (!reader.indexed()) os << "  " << reader.recoveryReason() << "\n";
  os << "Bag time: " << fixed(reader.beginTime(), 6) << " .. " << fixed(reader.endTime(), 6)
     << " s (" << fixed(duration, 3) << " s), " << total << " messages\n";
  os << "Topics (" << reader.topics().size() << "):\n";
  j["format"] = "ROS1 bag";
  j["path"] = path;
  j["size_bytes"] = reader.fileSize();
  j["indexed"] = reader.indexed();
  j["begin_time"] = reader.beginTime();
  j["end_time"] = reader.endTime();
  j["messages"] = total;
  json jt = json::array();
  std::size_t width = 0;
  for (const bag::BagTopic& t : reader.topics()) width = std::max(width, t.topic.size());
  for (const bag::BagTopic& t : reader.topics()) {
    const double rate = duration > 0.0 && t.messages > 1 ? (t.messages - 1) / duration : 0.0;
    os << "  " << std::left << std::setw(static_cast<int>(width)) << t.topic << "  "
       << std::setw(28) << t.datatype << std::right << std::setw(8) << t.messages;
    if (rate > 0.0) os << "  ~" << fixed(rate, 1) << " Hz";
    os << "\n";
    jt.push_back({{"topic", t.topic}, {"type", t.datatype}, {"messages", t.messages}});
  }
  j["topics"] = jt;
  if (conv) {
    const bag::BagLayout& l = conv->layout();
    os << "Layout: " << bag::toString(l.kind) << "\n";
    const auto show = [&](const char* name, const std::string& topic) {
      os << "  " << std::left << std::setw(14) << name << std::right
         << (topic.empty() ? "(none)" : topic) << "\n";
    };
    show("colour", l.color);
    show("depth", l.depth);
    if (!l.accel.empty()) {
      show("accelerometer", l.accel);
      show("gyroscope", l.gyro);
    } else {
      show("IMU", l.imu);
    }
    show("ground truth", l.groundtruth);
    show("odometry", l.odometry);
    os << "  depth " << (l.depth_aligned ? "aligned to colour" : "not aligned to colour") << "\n";
    os << "Calibration a conversion would use:\n";
    for (const std::string& c : conv->calibration()) os << "  " << c << "\n";
    if (!l.notes.empty()) os << "Notes:\n";
    for (const std::string& n : l.notes) os << "  " << n << "\n";
    j["layout"] = {{"kind", bag::toString(l.kind)},
                   {"color", l.color},
                   {"depth", l.depth},
                   {"imu", l.imu},
                   {"accel", l.accel},
                   {"gyro", l.gyro},
                   {"groundtruth", l.groundtruth},
                   {"odometry", l.odometry},
                   {"depth_aligned", l.depth_aligned}};
    j["calibration"] = conv->calibration();
    j["notes"] = l.notes;
    if (!l.odometry.empty()) describeWheels(path, settings, topics, stream, l, os, j);
  } else {
    os << "Layout: cannot convert without options: " << layout_error << "\n";
    j["layout_error"] = layout_error;
  }
  if (!reader.indexed()) {
    d.error = path + ": " + reader.recoveryReason() +
              (reader.damage().empty() ? "" : "; " + reader.damage());
    j["error"] = d.error;
  }
  d.text = os.str();
  d.json = j.dump(2);
  return d;
}

InputDescription describeTumFolder(const std::string& path) {
  InputDescription d;
  json j;
  std::ostringstream os;
  os << "TUM RGB-D folder: " << path << "\n";
  j["format"] = "TUM RGB-D folder";
  j["path"] = path;
  for (const char* name : {"rgb.txt", "depth.txt", "accelerometer.txt", "groundtruth.txt"}) {
    const std::string file = (fs::path(path) / name).string();
    if (!fs::exists(file)) {
      os << "  " << std::left << std::setw(18) << name << std::right << "absent\n";
      j["files"][name] = nullptr;
      continue;
    }
    const std::vector<double> t = listStamps(file);
    const double span = t.size() > 1 ? t.back() - t.front() : 0.0;
    os << "  " << std::left << std::setw(18) << name << std::right << std::setw(6) << t.size()
       << " entries";
    if (span > 0.0)
      os << ", " << fixed(t.front(), 6) << " .. " << fixed(t.back(), 6) << " s (" << fixed(span, 3)
         << " s, ~" << fixed((t.size() - 1) / span, 1) << " Hz)";
    os << "\n";
    j["files"][name] = {{"entries", t.size()},
                        {"first", t.empty() ? 0.0 : t.front()},
                        {"last", t.empty() ? 0.0 : t.back()}};
  }
  const std::string cam = detectTumCamera(path);
  if (cam.empty()) {
    os << "Camera: not recognised from the folder name (convert with --tum-camera "
          "fr1|fr2|fr3|ros)\n";
  } else {
    const PinholeCamera c = tumCamera(cam);
    os << "Camera: " << cam << " (from the folder name): fx " << c.fx << " fy " << c.fy << " cx "
       << c.cx << " cy " << c.cy << "\n";
  }
  j["camera"] = cam;
  os << "Note: TUM RGB-D has no gyroscope; accelerometer.txt holds the Kinect's accelerometer "
        "only.\n";
  d.text = os.str();
  d.json = j.dump(2);
  return d;
}

}  // namespace rgbdi::convert
