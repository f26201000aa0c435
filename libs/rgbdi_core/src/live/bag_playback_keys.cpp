#include "live/bag_playback_keys.h"

namespace rgbdi::live {

BagPlaybackKeys BagPlaybackKeys::load(const SensorKeys& k, bool with_topics) {
  BagPlaybackKeys b;
  const std::string config = k.getPath("config", false);
  const std::string yaml = k.getPath("camera_yaml", false);
  // Each file on its own first, so that an error names the key whose file it is.
  try {
    b.settings = convert::loadConversionSettings(config, "");
  } catch (const std::exception& e) {
    k.fail("config", e.what());
  }
  if (!yaml.empty()) {
    try {
      b.settings = convert::loadConversionSettings(config, yaml);
    } catch (const std::exception& e) {
      k.fail("camera_yaml", e.what());
    }
  }
  if (!config.empty()) b.given.push_back("config");
  if (!yaml.empty()) b.given.push_back("camera_yaml");
  if (!with_topics) return b;

  const std::string aligned = k.getEnum("depth_aligned", "auto", {"auto", "yes", "no"});
  if (aligned != "auto") b.input.depth_aligned = aligned == "yes";
  if (aligned != "auto") b.given.push_back("depth_aligned");
  bag::TopicOverrides& t = b.input.topics;
  const std::pair<const char*, std::string*> topics[] = {{"color_topic", &t.color},
                                                         {"depth_topic", &t.depth},
                                                         {"imu_topic", &t.imu},
                                                         {"accel_topic", &t.accel},
                                                         {"gyro_topic", &t.gyro},
                                                         {"color_info_topic", &t.color_info},
                                                         {"depth_info_topic", &t.depth_info}};
  for (const auto& [key, value] : topics) {
    *value = k.getString(key, "");
    if (!value->empty()) b.given.push_back(key);
  }
  return b;
}

std::string BagPlaybackKeys::givenList() const {
  std::string s;
  for (const std::string& g : given) s += (s.empty() ? "" : ", ") + g;
  return s;
}

}  // namespace rgbdi::live
