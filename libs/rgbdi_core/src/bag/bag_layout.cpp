#include "rgbdi/bag/bag_layout.h"

#include <nav_msgs/Odometry.h>

#include <algorithm>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>

namespace rgbdi::bag {
namespace {

const char* const kImage = "sensor_msgs/Image";
const char* const kCompressed = "sensor_msgs/CompressedImage";
const char* const kImu = "sensor_msgs/Imu";
const char* const kPose = "geometry_msgs/PoseStamped";
const char* const kCameraInfo = "sensor_msgs/CameraInfo";
const char* const kFloat32 = "std_msgs/Float32";
const char* const kTransform = "geometry_msgs/Transform";
const char* const kOdometry = "nav_msgs/Odometry";
const char* const kTfMessage = "tf2_msgs/TFMessage";

class Topics {
 public:
  explicit Topics(const std::vector<BagTopic>& list) {
    for (const BagTopic& t : list) by_name_[t.topic] = &t;
  }
  const BagTopic* find(const std::string& name) const {
    const auto it = by_name_.find(name);
    return it == by_name_.end() ? nullptr : it->second;
  }
  bool has(const std::string& name, const std::string& type) const {
    const BagTopic* t = find(name);
    return t && t->datatype == type;
  }
  const std::map<std::string, const BagTopic*>& all() const { return by_name_; }

 private:
  std::map<std::string, const BagTopic*> by_name_;
};

std::string parentOf(const std::string& topic) {
  const auto slash = topic.rfind('/');
  return slash == std::string::npos || slash == 0 ? std::string() : topic.substr(0, slash);
}

/// RealSense SDK recording: the first stream of each kind, by sorted topic name.
void detectRealSense(const Topics& topics, BagLayout& l) {
  static const std::regex stream_re(
      R"(^(/device_\d+/sensor_\d+/)(Color|Depth|Accel|Gyro)_(\d+)/(image|imu)/data$)");
  std::map<std::string, std::string> stream_prefix;  // kind -> "/device_0/sensor_1/Color_0/"
  std::map<std::string, std::string> sensor_prefix;  // kind -> "/device_0/sensor_1/"
  for (const auto& [name, t] : topics.all()) {
    std::smatch m;
    if (!std::regex_match(name, m, stream_re)) continue;
    const std::string kind = m[2];
    if (stream_prefix.count(kind)) continue;  // sorted: keep the first (device 0, stream 0)
    stream_prefix[kind] = m[1].str() + kind + "_" + m[3].str() + "/";
    sensor_prefix[kind] = m[1];
  }
  const auto topicOf = [&](const std::string& kind, const std::string& suffix) {
    const auto it = stream_prefix.find(kind);
    return it == stream_prefix.end() ? std::string() : it->second + suffix;
  };
  /// The stream's extrinsic topic "<stream>/tf/<reference>" (the SDK numbers the reference).
  const auto tfOf = [&](const std::string& kind) {
    const std::string prefix = topicOf(kind, "tf/");
    if (prefix.empty()) return std::string();
    for (const auto& [name, t] : topics.all())
      if (name.rfind(prefix, 0) == 0 && t->datatype == kTransform) return name;
    return std::string();
  };
  l.color = topicOf("Color", "image/data");
  l.depth = topicOf("Depth", "image/data");
  l.accel = topicOf("Accel", "imu/data");
  l.gyro = topicOf("Gyro", "imu/data");
  if (l.accel.empty() != l.gyro.empty()) {
    l.notes.push_back("the recording has only one of the Accel/Gyro streams: no IMU data written");
    l.accel.clear();
    l.gyro.clear();
  }
  if (!l.color.empty() && topics.has(topicOf("Color", "info/camera_info"), kCameraInfo))
    l.color_info = topicOf("Color", "info/camera_info");
  if (!l.depth.empty() && topics.has(topicOf("Depth", "info/camera_info"), kCameraInfo))
    l.depth_info = topicOf("Depth", "info/camera_info");
  if (!l.depth.empty() && topics.has(sensor_prefix["Depth"] + "option/Depth Units/value", kFloat32))
    l.depth_units = sensor_prefix["Depth"] + "option/Depth Units/value";
  l.color_tf = tfOf("Color");
  l.depth_tf = tfOf("Depth");
  l.imu_tf = l.accel.empty() ? std::string() : tfOf("Accel");
  if (l.imu_tf.empty() && !l.gyro.empty()) l.imu_tf = tfOf("Gyro");
  l.depth_aligned = false;
}

void detectDataset(const Topics& topics, BagLayout& l) {
  const auto first = [&](std::initializer_list<const char*> names,
                         std::initializer_list<const char*> types) {
    for (const char* n : names)
      for (const char* t : types)
        if (topics.has(n, t)) return std::string(n);
    return std::string();
  };
  l.color = first({"/camera/color/image_raw", "/camera/color/image_raw/compressed"},
                  {kImage, kCompressed});
  l.depth = first({"/camera/aligned_depth_to_color/image_raw",
                   "/camera/aligned_depth_to_color/image_raw/compressedDepth",
                   "/camera/aligned_depth_to_color/image_raw/compressed"},
                  {kImage, kCompressed});
  l.imu = first({"/camera/imu"}, {kImu});
  if (l.imu.empty() && topics.has("/camera/accel/sample", kImu) &&
      topics.has("/camera/gyro/sample", kImu)) {
    l.accel = "/camera/accel/sample";
    l.gyro = "/camera/gyro/sample";
  }
  // Ground truth: the motion-capture topic (/vrpn_client_node/<name>/pose), else the only pose.
  std::vector<std::string> poses, vrpn;
  for (const auto& [name, t] : topics.all()) {
    if (t->datatype != kPose) continue;
    poses.push_back(name);
    if (name.rfind("/vrpn_client_node/", 0) == 0) vrpn.push_back(name);
  }
  const std::vector<std::string>& candidates = vrpn.empty() ? poses : vrpn;
  if (!candidates.empty()) {
    l.groundtruth = candidates.front();
    if (poses.size() > 1)
      l.notes.push_back("several geometry_msgs/PoseStamped topics; ground truth from " +
                        l.groundtruth + " (choose another with --groundtruth-topic)");
  }
  l.depth_aligned = true;
}

void checkType(const Topics& topics, const std::string& topic,
               std::initializer_list<const char*> types, const std::string& what,
               const std::vector<BagTopic>& list, const std::string& path) {
  const BagTopic* t = topics.find(topic);
  if (!t)
    throw BagLayoutError(path + ": " + what + " topic '" + topic +
                         "' is not in the bag; its topics are:\n" + describeTopics(list));
  for (const char* ty : types)
    if (t->datatype == ty) return;
  std::string expected;
  for (const char* ty : types) expected += (expected.empty() ? "" : " or ") + std::string(ty);
  throw BagLayoutError(path + ": " + what + " topic '" + topic + "' has type " + t->datatype +
                       ", expected " + expected);
}

/// The wheel odometry: the named topic (checked), none, or the only nav_msgs/Odometry topic.
std::string resolveOdometry(const Topics& topics, const std::string& override_topic,
                            const std::vector<BagTopic>& list, const std::string& path) {
  std::string topic;
  if (override_topic == "none") return topic;
  if (!override_topic.empty()) {
    checkType(topics, override_topic, {kOdometry}, "odometry", list, path);
    topic = override_topic;
  } else {
    std::vector<std::string> found;
    for (const auto& [name, t] : topics.all())
      if (t->datatype == kOdometry) found.push_back(name);
    if (found.empty()) return topic;
    if (found.size() > 1) {
      std::string names;
      for (const std::string& n : found) names += (names.empty() ? "" : ", ") + n;
      throw BagLayoutError(path + ": several nav_msgs/Odometry topics (" + names +
                           "): name the wheel odometry with --odom-topic TOPIC, or leave it out "
                           "with --odom-topic none");
    }
    topic = found.front();
  }
  // Another definition under the same name would be decoded as garbage: refuse it.
  const std::string expected = ros::message_traits::MD5Sum<nav_msgs::Odometry>::value();
  const BagTopic* t = topics.find(topic);
  if (!t->md5sum.empty() && t->md5sum != "*" && t->md5sum != expected)
    throw BagLayoutError(path + ": odometry topic '" + topic + "' has message definition md5sum " +
                         t->md5sum + ", expected " + expected +
                         " (nav_msgs/Odometry of ROS1); leave it out with --odom-topic none");
  return topic;
}

/// Applies one override: "" keeps the detected topic, "none" disables it, a name replaces it.
bool apply(const std::string& override_topic, std::string& slot) {
  if (override_topic.empty()) return false;
  slot = override_topic == "none" ? std::string() : override_topic;
  return true;
}

}  // namespace

std::string toString(BagLayoutKind k) {
  switch (k) {
    case BagLayoutKind::Dataset:
      return "VINS-RGBD dataset layout";
    case BagLayoutKind::RealSense:
      return "RealSense SDK recording layout";
    case BagLayoutKind::Custom:
      return "topics given on the command line";
  }
  return "?";
}

std::vector<std::string> BagLayout::streamedTopics() const {
  std::vector<std::string> t;
  for (const std::string* s : {&color, &depth, &imu, &accel, &gyro, &groundtruth, &odometry})
    if (!s->empty() && std::find(t.begin(), t.end(), *s) == t.end()) t.push_back(*s);
  return t;
}

std::string describeTopics(const std::vector<BagTopic>& topics, const std::string& indent) {
  std::size_t width = 0;
  for (const BagTopic& t : topics) width = std::max(width, t.topic.size());
  std::ostringstream os;
  for (const BagTopic& t : topics)
    os << indent << std::left << std::setw(static_cast<int>(width)) << t.topic << "  "
       << std::setw(28) << t.datatype << " " << std::right << t.messages << " messages\n";
  if (topics.empty()) os << indent << "(no topics)\n";
  return os.str();
}

BagLayout resolveBagLayout(const std::vector<BagTopic>& list, const TopicOverrides& o,
                           std::optional<bool> depth_aligned, const std::string& path) {
  const Topics topics(list);
  BagLayout l;
  bool realsense = false;
  for (const auto& [name, t] : topics.all())
    if (std::regex_search(name, std::regex(R"(^/device_\d+/sensor_\d+/)"))) realsense = true;
  if (realsense) {
    l.kind = BagLayoutKind::RealSense;
    detectRealSense(topics, l);
  } else {
    l.kind = BagLayoutKind::Dataset;
    detectDataset(topics, l);
  }

  bool custom = false;
  custom |= apply(o.color, l.color);
  custom |= apply(o.depth, l.depth);
  if (apply(o.imu, l.imu)) {
    custom = true;
    if (!l.imu.empty()) {
      l.accel.clear();
      l.gyro.clear();
    }
  }
  const bool accel_given = apply(o.accel, l.accel), gyro_given = apply(o.gyro, l.gyro);
  if (accel_given || gyro_given) {
    custom = true;
    if (l.accel.empty() != l.gyro.empty())
      throw BagLayoutError(path + ": --accel-topic and --gyro-topic must be given together");
    if (!l.accel.empty()) l.imu.clear();
  }
  custom |= apply(o.groundtruth, l.groundtruth);
  custom |= apply(o.color_info, l.color_info);
  custom |= apply(o.depth_info, l.depth_info);
  if (custom && l.kind == BagLayoutKind::Dataset) l.kind = BagLayoutKind::Custom;

  // Automatic camera_info next to the image topics (e.g. realsense-ros: /camera/color/camera_info).
  if (o.color_info.empty() && l.color_info.empty() && !l.color.empty()) {
    std::string dir = parentOf(l.color);
    if (l.color.size() > 11 && l.color.compare(l.color.size() - 11, 11, "/compressed") == 0)
      dir = parentOf(dir);
    if (topics.has(dir + "/camera_info", kCameraInfo)) l.color_info = dir + "/camera_info";
  }
  if (o.depth_info.empty() && l.depth_info.empty() && !l.depth.empty()) {
    std::string dir = parentOf(l.depth);
    if (dir.size() > 10 && (dir.rfind("/image_raw") == dir.size() - 10)) dir = parentOf(dir);
    if (topics.has(dir + "/camera_info", kCameraInfo)) l.depth_info = dir + "/camera_info";
  }

  if (l.color.empty() && l.depth.empty()) {
    throw BagLayoutError(
        path + ": no colour or depth image topic found (looked for " +
        (realsense ? std::string("/device_N/sensor_N/{Color,Depth}_N/image/data")
                   : std::string("/camera/color/image_raw and "
                                 "/camera/aligned_depth_to_color/image_raw")) +
        "; name them with --color-topic / --depth-topic). The bag's topics are:\n" +
        describeTopics(list));
  }
  if (!l.color.empty()) checkType(topics, l.color, {kImage, kCompressed}, "colour", list, path);
  if (!l.depth.empty()) checkType(topics, l.depth, {kImage, kCompressed}, "depth", list, path);
  if (!l.imu.empty()) checkType(topics, l.imu, {kImu}, "IMU", list, path);
  if (!l.accel.empty()) checkType(topics, l.accel, {kImu}, "accelerometer", list, path);
  if (!l.gyro.empty()) checkType(topics, l.gyro, {kImu}, "gyroscope", list, path);
  if (!l.groundtruth.empty()) checkType(topics, l.groundtruth, {kPose}, "ground-truth", list, path);
  if (!l.color_info.empty())
    checkType(topics, l.color_info, {kCameraInfo}, "colour camera_info", list, path);
  if (!l.depth_info.empty())
    checkType(topics, l.depth_info, {kCameraInfo}, "depth camera_info", list, path);
  l.odometry = resolveOdometry(topics, o.odometry, list, path);
  if (topics.has("/tf_static", kTfMessage)) l.tf_static = "/tf_static";
  l.color_compressed = !l.color.empty() && topics.find(l.color)->datatype == kCompressed;
  l.depth_compressed = !l.depth.empty() && topics.find(l.depth)->datatype == kCompressed;
  if (depth_aligned) l.depth_aligned = *depth_aligned;

  if (l.color.empty()) l.notes.push_back("no colour image topic: depth-only observations");
  if (l.depth.empty())
    l.notes.push_back("no depth image topic: colour frames have no partner and are dropped");
  if (l.imu.empty() && l.accel.empty())
    l.notes.push_back(std::string("no IMU topic") +
                      (realsense ? " (the recording has no Accel/Gyro streams)"
                                 : " (looked for /camera/imu; name one with --imu-topic)") +
                      ": no CObservationIMU written");
  if (l.groundtruth.empty())
    l.notes.push_back("no geometry_msgs/PoseStamped topic: no ground truth written");
  return l;
}

}  // namespace rgbdi::bag
