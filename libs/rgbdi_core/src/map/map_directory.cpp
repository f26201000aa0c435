// saveMap / loadMap / checkCompatible (rgbdi/map/map_directory.h, doc/maps.md).
#include "rgbdi/map/map_directory.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>
#include <sstream>

#include "map/file_io.h"
#include "map/loops_file.h"
#include "map/manifest_json.h"
#include "map/places_file.h"
#include "map/version_publisher.h"
#include "mapping/pose_check.h"
#include "rgbdi/mapping/map_export.h"

namespace rgbdi::map {
namespace {

/// The files loadMap reads (the others are for users' tools).
const char* const kDataFiles[] = {kKeyframesFile, kPlacesFile, kLoopsFile};

std::string descriptorText(const std::string& type, std::uint32_t bytes) {
  return "\"" + type + "\" (" + std::to_string(bytes) + " bytes)";
}

/// Empty string when `d` agrees with the manifest, otherwise what is wrong. A set without
/// keypoints may carry no type (a keyframe without colour image).
std::string descriptorMismatch(const mapping::DescriptorSet& d, const MapManifest& m) {
  if (!d.consistent()) return "descriptor data, keypoints and keypoint points disagree in size";
  if (d.size() == 0 && d.type.empty()) return {};
  if (d.type != m.descriptor_type || d.bytes_per_descriptor != m.descriptor_bytes)
    return "descriptors " + descriptorText(d.type, d.bytes_per_descriptor) +
           " but the manifest says " + descriptorText(m.descriptor_type, m.descriptor_bytes);
  return {};
}

/// Checks what save and load both require; `fail` throws.
void checkConsistency(const MapView& map, const std::function<void(const std::string&)>& fail) {
  const MapManifest& m = map.manifest;
  std::set<std::uint64_t> ids;
  std::uint64_t max_id = 0;
  int max_segment = -1;
  for (std::size_t i = 0; i < map.places.size(); ++i) {
    const loop::LoopKeyframe& p = *map.places[i].keyframe;
    const std::string what = "place " + std::to_string(p.id);
    if (i > 0 && map.places[i - 1].keyframe->id >= p.id)
      fail(what + ": place ids are not strictly increasing");
    if (!mapping::detail::isRigid(map.places[i].T_world_body) ||
        !mapping::detail::isRigid(p.T_world_body_odom))
      fail(what + ": a pose is not a finite rigid transform");
    if (p.segment < 0) fail(what + ": negative segment");
    const std::string d = descriptorMismatch(p.descriptors, m);
    if (!d.empty()) fail(what + ": " + d);
    ids.insert(p.id);
    max_id = std::max(max_id, p.id);
    max_segment = std::max(max_segment, p.segment);
  }
  for (const mapping::Keyframe* k : map.keyframes) {
    const std::string d = descriptorMismatch(k->descriptors, m);
    if (!d.empty()) fail("store keyframe " + std::to_string(k->id) + ": " + d);
    max_id = std::max(max_id, k->id);
  }
  for (const MapLoopEdge& e : map.loops) {
    if (!ids.count(e.from_id) || !ids.count(e.to_id))
      fail("loop " + std::to_string(e.from_id) + " -> " + std::to_string(e.to_id) +
           " joins a keyframe that is not a place");
    if (!mapping::detail::isRigid(e.T_from_to))
      fail("loop " + std::to_string(e.from_id) + " -> " + std::to_string(e.to_id) +
           ": T_from_to is not a finite rigid transform");
  }
  if ((!map.places.empty() || !map.keyframes.empty()) && m.next_keyframe_id <= max_id)
    fail("next_keyframe_id " + std::to_string(m.next_keyframe_id) +
         " is not above the largest keyframe id " + std::to_string(max_id));
  if (m.next_segment <= max_segment)
    fail("next_segment " + std::to_string(m.next_segment) + " is not above the largest segment " +
         std::to_string(max_segment));
  if (m.sessions < 0) fail("negative session count");
}

template <typename F>
void wrapErrors(const std::string& file, F&& f) {
  try {
    f();
  } catch (const MapError&) {
    throw;
  } catch (const std::exception& e) {
    throw MapError(file + ": " + e.what());
  }
}

std::string countMismatch(const char* what, std::uint64_t manifest, std::uint64_t file) {
  return "the manifest says " + std::to_string(manifest) + " " + what + ", the file holds " +
         std::to_string(file);
}

std::string formatValue(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

}  // namespace

output::PoseGraph mapPoseGraph(const MapView& map,
                               const Eigen::Matrix<double, 6, 6>& odometry_information,
                               const Eigen::Matrix<double, 6, 6>& loop_information) {
  output::PoseGraph g;
  for (std::size_t i = 0; i < map.places.size(); ++i) {
    const loop::LoopKeyframe& p = *map.places[i].keyframe;
    g.nodes.push_back({p.id, p.t, map.places[i].T_world_body});
    if (i == 0 || map.places[i - 1].keyframe->segment != p.segment) continue;
    const loop::LoopKeyframe& q = *map.places[i - 1].keyframe;
    output::PoseGraphEdge e;
    e.from = q.id;
    e.to = p.id;
    e.T_from_to = q.T_world_body_odom.inverse() * p.T_world_body_odom;
    e.information = odometry_information;
    e.kind = "odometry";
    g.edges.push_back(e);
  }
  for (const MapLoopEdge& l : map.loops) {
    if (!l.active) continue;
    output::PoseGraphEdge e;
    e.from = l.from_id;
    e.to = l.to_id;
    e.T_from_to = l.T_from_to;
    e.information = loop_information;
    e.kind = "loop";
    g.edges.push_back(e);
  }
  if (!g.nodes.empty()) g.root = g.nodes.front().id;
  return g;
}

output::PoseGraph mapPoseGraph(const MapData& map,
                               const Eigen::Matrix<double, 6, 6>& odometry_information,
                               const Eigen::Matrix<double, 6, 6>& loop_information) {
  return mapPoseGraph(MapView::of(map), odometry_information, loop_information);
}

void saveMap(const std::string& map_dir, const MapData& map, const MapExtras& extras) {
  saveMap(map_dir, MapView::of(map), extras);
}

void saveMap(const std::string& map_dir, const MapView& map, const MapExtras& extras) {
  checkConsistency(map, [&](const std::string& what) {
    throw MapError(map_dir + ": cannot save the map: " + what);
  });
  const auto step = [&](const std::string& s) {
    if (extras.after_step) extras.after_step(s);
  };
  detail::VersionPublisher publisher(map_dir);
  const std::string dir = publisher.stagingDir();
  step("staged");
  std::vector<std::string> written;
  const auto done = [&](const char* name) {
    written.push_back(name);
    step(name);
  };

  wrapErrors(dir + "/" + kKeyframesFile, [&] {
    mapping::KeyframeStore::save(dir + "/" + kKeyframesFile, map.keyframes);
    detail::fsyncPath(dir + "/" + kKeyframesFile);
  });
  done(kKeyframesFile);
  detail::writePlacesFile(dir + "/" + kPlacesFile, map.places);
  done(kPlacesFile);
  detail::writeLoopsFile(dir + "/" + kLoopsFile, map.loops);
  done(kLoopsFile);
  wrapErrors(dir + "/" + kPoseGraphFile, [&] {
    const output::PoseGraph g =
        mapPoseGraph(map, extras.odometry_information, extras.loop_information);
    output::writePoseGraph(dir + "/" + kPoseGraphFile, g.nodes, g.edges);
    detail::fsyncPath(dir + "/" + kPoseGraphFile);
  });
  done(kPoseGraphFile);
  if (extras.point_map) {
    wrapErrors(dir + "/" + kPointsFile, [&] {
      mapping::writePly(dir + "/" + kPointsFile, *extras.point_map);
      detail::fsyncPath(dir + "/" + kPointsFile);
    });
    done(kPointsFile);
  }
  if (extras.occupancy) {
    wrapErrors(dir + "/" + kOccupancyFile, [&] {
      extras.occupancy->write(dir + "/" + kOccupancyFile);
      detail::fsyncPath(dir + "/" + kOccupancyFile);
    });
    done(kOccupancyFile);
  }

  // The manifest last: it describes files that are complete on disk.
  detail::ManifestContent content;
  content.manifest = map.manifest;
  content.manifest.format_version = kMapFormatVersion;
  content.counts = detail::countsOf(map);
  for (const std::string& name : written)
    content.files[name] = detail::digestFile(dir + "/" + name);
  detail::writeDurably(dir + "/" + kManifestFile, detail::manifestToJson(content));
  step(kManifestFile);

  publisher.publish(extras.after_step);
  publisher.removeOldVersions();
  step("cleaned");
}

MapData loadMap(const std::string& map_dir) {
  // Resolve the link once: every file then comes from the same version.
  std::error_code ec;
  const std::filesystem::path resolved = std::filesystem::canonical(map_dir, ec);
  if (ec) throw MapError(map_dir + ": no map directory here (" + ec.message() + ")");
  const std::string dir = resolved.string();
  const auto path = [&](const std::string& name) { return dir + "/" + name; };

  const std::string manifest_path = path(kManifestFile);
  struct stat st {};
  if (::stat(manifest_path.c_str(), &st) != 0)
    throw MapError(manifest_path +
                   ": missing manifest (not a map directory, or an incomplete "
                   "copy): " +
                   std::strerror(errno));
  std::string text;
  wrapErrors(manifest_path, [&] {
    const std::vector<char> bytes = detail::readWholeFile(manifest_path);
    text.assign(bytes.begin(), bytes.end());
  });
  const detail::ManifestContent content = detail::parseManifest(text, manifest_path);

  for (const char* name : kDataFiles)
    if (!content.files.count(name))
      throw MapError(manifest_path + ": does not list the data file " + name);
  for (const auto& [name, expected] : content.files) {
    const std::string file = path(name);
    if (::stat(file.c_str(), &st) != 0)
      throw MapError(file + ": missing (listed in manifest.json): " + std::strerror(errno));
    if (static_cast<std::uint64_t>(st.st_size) != expected.bytes)
      throw MapError(file + ": " + std::to_string(st.st_size) + " bytes, manifest.json says " +
                     std::to_string(expected.bytes) + " (truncated or replaced file)");
  }
  for (const char* name : kDataFiles) {
    const detail::FileDigest d = detail::digestFile(path(name));
    const detail::FileDigest& expected = content.files.at(name);
    if (d.fnv1a64 != expected.fnv1a64)
      throw MapError(path(name) + ": checksum (FNV-1a 64) " + detail::hex64(d.fnv1a64) +
                     ", manifest.json says " + detail::hex64(expected.fnv1a64) + " (corrupt file)");
  }

  MapData map;
  map.manifest = content.manifest;
  wrapErrors(path(kKeyframesFile),
             [&] { map.keyframes = mapping::KeyframeStore::load(path(kKeyframesFile)); });
  map.places = detail::readPlacesFile(path(kPlacesFile));
  map.loops = detail::readLoopsFile(path(kLoopsFile));

  const MapView view = MapView::of(map);
  const detail::MapCounts c = detail::countsOf(view);
  const detail::MapCounts& e = content.counts;
  if (c.places != e.places)
    throw MapError(path(kPlacesFile) + ": " + countMismatch("places", e.places, c.places));
  if (c.place_keypoints != e.place_keypoints)
    throw MapError(path(kPlacesFile) + ": " +
                   countMismatch("keypoints", e.place_keypoints, c.place_keypoints));
  if (c.loops != e.loops)
    throw MapError(path(kLoopsFile) + ": " + countMismatch("loop edges", e.loops, c.loops));
  if (c.keyframes != e.keyframes)
    throw MapError(path(kKeyframesFile) + ": " +
                   countMismatch("keyframes", e.keyframes, c.keyframes));
  if (c.keyframe_points != e.keyframe_points)
    throw MapError(path(kKeyframesFile) + ": " +
                   countMismatch("kept points", e.keyframe_points, c.keyframe_points));
  checkConsistency(view, [&](const std::string& what) {
    // Name the file that holds the offending record.
    const char* file = what.rfind("loop", 0) == 0             ? kLoopsFile
                       : what.rfind("store keyframe", 0) == 0 ? kKeyframesFile
                       : what.rfind("place", 0) == 0          ? kPlacesFile
                                                              : kManifestFile;
    throw MapError(path(file) + ": " + what);
  });
  return map;
}

void checkCompatible(const MapManifest& m, const PinholeCamera& camera,
                     const Eigen::Isometry3d& T_body_cam, const std::string& descriptor_type,
                     const std::string& map_dir) {
  std::vector<std::string> diffs;
  const auto differs = [&](const std::string& what, double map_value, double run_value) {
    if (!(std::abs(map_value - run_value) <= kCalibrationTolerance))
      diffs.push_back(what + " " + formatValue(map_value) + " (map) vs " + formatValue(run_value) +
                      " (this run)");
  };
  if (m.camera.width != camera.width || m.camera.height != camera.height)
    diffs.push_back("image size " + std::to_string(m.camera.width) + "x" +
                    std::to_string(m.camera.height) + " (map) vs " + std::to_string(camera.width) +
                    "x" + std::to_string(camera.height) + " (this run)");
  differs("fx", m.camera.fx, camera.fx);
  differs("fy", m.camera.fy, camera.fy);
  differs("cx", m.camera.cx, camera.cx);
  differs("cy", m.camera.cy, camera.cy);
  const char* dist_names[5] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) differs(dist_names[i], m.camera.dist[i], camera.dist[i]);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      differs("T_body_cam(" + std::to_string(r) + "," + std::to_string(c) + ")",
              m.T_body_cam.matrix()(r, c), T_body_cam.matrix()(r, c));
  if (m.descriptor_type != descriptor_type)
    diffs.push_back("descriptor type \"" + m.descriptor_type + "\" (map) vs \"" + descriptor_type +
                    "\" (this run)");
  if (diffs.empty()) return;
  std::string msg = map_dir + ": the map was built with another calibration or descriptor type: ";
  for (std::size_t i = 0; i < diffs.size(); ++i) msg += (i ? "; " : "") + diffs[i];
  throw MapError(msg);
}

}  // namespace rgbdi::map
