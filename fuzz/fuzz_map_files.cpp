// Fuzz target: the data files of a map directory that rgbdi's own parsers read (doc/maps.md):
// places.bin (loop-closure keyframes with descriptors), loops.txt (loop edges) and
// manifest.json. The first input byte picks the file (modulo 3), the rest is its content.
// loadMap checks every data file's size and checksum against the manifest before parsing it,
// so fuzzing through loadMap would stop at the checksum; the parsers are fed directly (a
// manifest with matching checksums is only a few lines of work for a broken or hostile writer).
// keyframes.bin has a target of its own (fuzz_keyframe_store). Documented refusal: MapError
// naming the file, the record or line and what is wrong.
#include <Eigen/Geometry>
#include <filesystem>

#include "fuzz_target.h"
#include "map/loops_file.h"
#include "map/manifest_json.h"
#include "map/places_file.h"
#include "rgbdi/map/map_directory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t* content = data + 1;
  const std::size_t content_size = size - 1;
  try {
    switch (data[0] % 3) {
      case 0:
        (void)rgbdi::map::detail::readPlacesFile(
            rgbdi::fuzz::writeScratchFile("places.bin", content, content_size));
        break;
      case 1:
        (void)rgbdi::map::detail::readLoopsFile(
            rgbdi::fuzz::writeScratchFile("loops.txt", content, content_size));
        break;
      default:
        (void)rgbdi::map::detail::parseManifest(
            std::string(reinterpret_cast<const char*>(content), content_size), "manifest.json");
        break;
    }
  } catch (const rgbdi::map::MapError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

namespace {

/// A small map as saveMap writes it: two segments, keypoints with and without depth, a place
/// without keypoints, an active and a rolled-back loop, a store keyframe with a kept point.
map::MapData seedMap() {
  map::MapData m;
  map::MapManifest& mf = m.manifest;
  mf.camera.width = 640;
  mf.camera.height = 480;
  mf.camera.fx = 615.25;
  mf.camera.fy = 614.75;
  mf.camera.cx = 319.5;
  mf.camera.cy = 241.25;
  mf.camera.dist = {0.12, -0.25, 1e-4, -2e-4, 0.01};
  mf.T_body_cam.translation() = Eigen::Vector3d(0.01, 0.02, 0.03);
  mf.has_groundtruth_alignment = true;
  mf.T_groundtruth_world.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).matrix();
  mf.descriptor_type = "ORB-256";
  mf.descriptor_bytes = 32;
  mf.next_segment = 2;
  mf.sessions = 1;
  mf.index_parameters = "place_min_score = 0.05\n";
  for (int i = 0; i < 3; ++i) {
    loop::LoopKeyframe p;
    p.id = 3 + 7 * static_cast<std::uint64_t>(i);
    p.segment = i < 2 ? 0 : 1;
    p.t = 1.7e9 + 0.4 * i;
    p.T_world_body_odom.translation() = Eigen::Vector3d(0.3 * i, 0.1, 0.0);
    p.T_world_body = p.T_world_body_odom;
    p.travelled_m = 0.3 * i;
    p.descriptors.type = "ORB-256";
    p.descriptors.bytes_per_descriptor = 32;
    if (i != 1) {  // place 1 saw no colour: no keypoints
      for (int k = 0; k < 2; ++k) {
        p.descriptors.keypoints_uv.emplace_back(100.0f + 50.0f * k, 200.0f);
        p.descriptors.keypoints_p_cam.emplace_back(0.1f * k, 0.2f, 1.5f);
        for (int b = 0; b < 32; ++b)
          p.descriptors.data.push_back(static_cast<std::uint8_t>(17 * b + 3 * k + i));
      }
    }
    m.places.push_back(p);
  }
  mf.next_keyframe_id = m.places.back().id + 5;
  for (int active = 0; active < 2; ++active) {
    map::MapLoopEdge e;
    e.from_id = m.places[0].id;
    e.to_id = m.places[2].id;
    e.T_from_to.translation() = Eigen::Vector3d(0.05, -0.02, 0.0);
    e.active = active == 1;
    m.loops.push_back(e);
  }
  mapping::Keyframe kf;
  kf.id = m.places[0].id;
  kf.t = m.places[0].t;
  mapping::MapPoint point;
  point.p_cam = Eigen::Vector3f(0.1f, 0.2f, 1.5f);
  point.rgb = mapping::Rgb{10, 20, 30};
  kf.points.push_back(point);
  kf.descriptors = m.places[0].descriptors;
  m.keyframes.add(kf);
  return m;
}

}  // namespace

std::vector<std::string> rgbdiFuzzSeeds() {
  const std::string dir = scratchDir("map_seeds");
  map::saveMap(dir + "/map", seedMap());
  std::vector<std::string> seeds;
  const char* files[] = {map::kPlacesFile, map::kLoopsFile, map::kManifestFile};
  for (char selector = 0; selector < 3; ++selector)
    seeds.push_back(std::string(1, selector) +
                    readFileBytes(dir + "/map/" + files[static_cast<int>(selector)]));
  std::filesystem::remove_all(dir);
  return seeds;
}

}  // namespace rgbdi::fuzz
