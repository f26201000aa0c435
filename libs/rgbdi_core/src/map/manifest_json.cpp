#include "map/manifest_json.h"

#include <limits>
#include <nlohmann/json.hpp>

#include "rgbdi/map/map_directory.h"

namespace rgbdi::map::detail {
namespace {

using nlohmann::json;

const char* const kFormatName = "rgbdi-map";

json poseToJson(const Eigen::Isometry3d& T) {
  json rows = json::array();
  for (int r = 0; r < 3; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(T.matrix()(r, c));
    rows.push_back(row);
  }
  return rows;
}

/// Reads keys of one JSON object, naming the key in errors.
class Fields {
 public:
  Fields(const json& j, std::string where, const std::string& path)
      : j_(j), where_(std::move(where)), path_(path) {
    if (!j_.is_object()) fail("is not a JSON object");
  }
  const json& at(const char* key) const {
    const auto it = j_.find(key);
    if (it == j_.end()) fail(std::string("missing key \"") + key + "\"");
    return *it;
  }
  template <typename T>
  T get(const char* key) const {
    const json& v = at(key);
    try {
      if constexpr (std::is_same_v<T, std::string>) {
        if (!v.is_string()) throw std::runtime_error("not a string");
      } else if constexpr (std::is_floating_point_v<T>) {
        if (!v.is_number()) throw std::runtime_error("not a number");
      } else if constexpr (std::is_unsigned_v<T>) {
        if (!v.is_number_unsigned()) throw std::runtime_error("not a non-negative integer");
        if (v.get<std::uint64_t>() > std::numeric_limits<T>::max()) throw outOfRange<T>(v);
      } else {
        if (!v.is_number_integer()) throw std::runtime_error("not an integer");
        // json converts integers to a narrower type silently (4294967936 read as an int is 640).
        const bool fits =
            v.is_number_unsigned()
                ? v.get<std::uint64_t>() <= std::uint64_t{std::numeric_limits<T>::max()}
                : v.get<std::int64_t>() >= std::numeric_limits<T>::min() &&
                      v.get<std::int64_t>() <= std::numeric_limits<T>::max();
        if (!fits) throw outOfRange<T>(v);
      }
      return v.get<T>();
    } catch (const std::exception& e) {
      fail(std::string("key \"") + key + "\": " + e.what());
    }
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw MapError(path_ + ": " + where_ + " " + what);
  }

 private:
  template <typename T>
  static std::runtime_error outOfRange(const json& v) {
    return std::runtime_error(v.dump() + " is out of range (" +
                              std::to_string(std::numeric_limits<T>::min()) + " to " +
                              std::to_string(std::numeric_limits<T>::max()) + ")");
  }

  const json& j_;
  std::string where_;
  const std::string& path_;
};

Eigen::Isometry3d poseFromJson(const json& j, const std::string& what, const std::string& path) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (!j.is_array() || j.size() != 3)
    throw MapError(path + ": " + what + " is not 3 rows of 4 numbers");
  for (int r = 0; r < 3; ++r) {
    const json& row = j[static_cast<std::size_t>(r)];
    if (!row.is_array() || row.size() != 4)
      throw MapError(path + ": " + what + " is not 3 rows of 4 numbers");
    for (int c = 0; c < 4; ++c) {
      const json& v = row[static_cast<std::size_t>(c)];
      if (!v.is_number())
        throw MapError(path + ": " + what + " holds a value that is not a number");
      T.matrix()(r, c) = v.get<double>();
    }
  }
  return T;
}

}  // namespace

std::string manifestToJson(const ManifestContent& content) {
  const MapManifest& m = content.manifest;
  json j;
  j["format"] = kFormatName;
  j["format_version"] = m.format_version;
  j["camera"] = {{"width", m.camera.width},
                 {"height", m.camera.height},
                 {"fx", m.camera.fx},
                 {"fy", m.camera.fy},
                 {"cx", m.camera.cx},
                 {"cy", m.camera.cy},
                 {"distortion_k1_k2_p1_p2_k3", m.camera.dist}};
  j["T_body_cam"] = poseToJson(m.T_body_cam);
  j["descriptor_type"] = m.descriptor_type;
  j["descriptor_bytes"] = m.descriptor_bytes;
  j["next_keyframe_id"] = m.next_keyframe_id;
  j["next_segment"] = m.next_segment;
  j["sessions"] = m.sessions;
  j["index_parameters"] = m.index_parameters;
  j["T_groundtruth_world"] =
      m.has_groundtruth_alignment ? poseToJson(m.T_groundtruth_world) : json();
  j["world_frame"] = m.world_frame;
  j["pose_convention"] = m.pose_convention;
  const MapCounts& c = content.counts;
  j["counts"] = {{"places", c.places},
                 {"place_keypoints", c.place_keypoints},
                 {"loops", c.loops},
                 {"keyframes", c.keyframes},
                 {"keyframe_points", c.keyframe_points}};
  json files = json::object();
  for (const auto& [name, d] : content.files)
    files[name] = {{"bytes", d.bytes}, {"fnv1a64", hex64(d.fnv1a64)}};
  j["files"] = files;
  return j.dump(2) + "\n";
}

ManifestContent parseManifest(const std::string& text, const std::string& path) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond double's range ("1.0e2815"; fuzzing,
    // doc/robustness.md finding 22), which escaped as an uncaught exception before.
    throw MapError(path + ": not valid JSON (" + e.what() + ")");
  }
  const Fields top(j, "manifest", path);
  if (top.get<std::string>("format") != kFormatName)
    top.fail("is not an rgbdi map manifest (\"format\" is not \"rgbdi-map\")");
  ManifestContent out;
  MapManifest& m = out.manifest;
  // The version first: another version may have other keys.
  m.format_version = top.get<int>("format_version");
  if (m.format_version != kMapFormatVersion)
    throw MapError(path + ": map format version " + std::to_string(m.format_version) +
                   ", this build reads version " + std::to_string(kMapFormatVersion) + " only");

  const Fields cam(top.at("camera"), "camera", path);
  m.camera.width = cam.get<int>("width");
  m.camera.height = cam.get<int>("height");
  m.camera.fx = cam.get<double>("fx");
  m.camera.fy = cam.get<double>("fy");
  m.camera.cx = cam.get<double>("cx");
  m.camera.cy = cam.get<double>("cy");
  const json& dist = cam.at("distortion_k1_k2_p1_p2_k3");
  if (!dist.is_array() || dist.size() != 5)
    cam.fail("key \"distortion_k1_k2_p1_p2_k3\": not 5 numbers");
  for (std::size_t i = 0; i < 5; ++i) {
    if (!dist[i].is_number()) cam.fail("key \"distortion_k1_k2_p1_p2_k3\": not 5 numbers");
    m.camera.dist[i] = dist[i].get<double>();
  }
  m.T_body_cam = poseFromJson(top.at("T_body_cam"), "T_body_cam", path);
  m.descriptor_type = top.get<std::string>("descriptor_type");
  m.descriptor_bytes = top.get<std::uint32_t>("descriptor_bytes");
  m.next_keyframe_id = top.get<std::uint64_t>("next_keyframe_id");
  m.next_segment = top.get<int>("next_segment");
  m.sessions = top.get<int>("sessions");
  m.index_parameters = top.get<std::string>("index_parameters");
  if (j.contains("T_groundtruth_world") && !j.at("T_groundtruth_world").is_null()) {
    m.has_groundtruth_alignment = true;
    m.T_groundtruth_world =
        poseFromJson(top.at("T_groundtruth_world"), "T_groundtruth_world", path);
  }
  m.world_frame = top.get<std::string>("world_frame");
  m.pose_convention = top.get<std::string>("pose_convention");

  const Fields counts(top.at("counts"), "counts", path);
  out.counts.places = counts.get<std::uint64_t>("places");
  out.counts.place_keypoints = counts.get<std::uint64_t>("place_keypoints");
  out.counts.loops = counts.get<std::uint64_t>("loops");
  out.counts.keyframes = counts.get<std::uint64_t>("keyframes");
  out.counts.keyframe_points = counts.get<std::uint64_t>("keyframe_points");

  const json& files = top.at("files");
  if (!files.is_object()) top.fail("key \"files\" is not a JSON object");
  for (auto it = files.begin(); it != files.end(); ++it) {
    const Fields f(it.value(), "files/" + it.key(), path);
    FileDigest d;
    d.bytes = f.get<std::uint64_t>("bytes");
    const std::string hex = f.get<std::string>("fnv1a64");
    if (hex.size() != 16 || hex.find_first_not_of("0123456789abcdef") != std::string::npos)
      f.fail("key \"fnv1a64\": not 16 lower-case hex digits");
    d.fnv1a64 = std::stoull(hex, nullptr, 16);
    if (it.key().find('/') != std::string::npos || it.key() == "." || it.key() == "..")
      f.fail("is not a plain file name");
    out.files[it.key()] = d;
  }
  return out;
}

MapCounts countsOf(const MapView& map) {
  MapCounts c;
  c.places = map.places.size();
  for (const MapView::Place& p : map.places) c.place_keypoints += p.keyframe->descriptors.size();
  c.loops = map.loops.size();
  c.keyframes = map.keyframes.size();
  for (const mapping::Keyframe* k : map.keyframes) c.keyframe_points += k->points.size();
  return c;
}

}  // namespace rgbdi::map::detail
