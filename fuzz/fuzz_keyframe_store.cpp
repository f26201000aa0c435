// Fuzz target: the keyframe file of mapping::KeyframeStore (save/load of a map's keyframes).
// Documented refusal: KeyframeFileError naming the file, the record and what is wrong.
#include <filesystem>

#include "fuzz_target.h"
#include "rgbdi/mapping/keyframe_store.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rgbdi::fuzz::writeScratchFile("keyframes.bin", data, size);
  try {
    const auto store = rgbdi::mapping::KeyframeStore::load(path);
    (void)store.pointCount();
  } catch (const rgbdi::mapping::KeyframeFileError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  using namespace mapping;
  const std::string dir = scratchDir("keyframe_seeds");
  std::vector<std::string> seeds;
  for (int variant = 0; variant < 2; ++variant) {
    KeyframeStore store;
    for (std::uint64_t id = 1; id <= 2; ++id) {
      Keyframe kf;
      kf.id = id;
      kf.frame_index = 10 * id;
      kf.t = 100.0 + id;
      kf.T_world_cam.translation() = Eigen::Vector3d(0.1 * id, 0.0, 0.2);
      KeyframeFeature feat;
      feat.id = 7 + id;
      feat.uv = Eigen::Vector2f(3.5f, 4.5f);
      feat.has_position = true;
      feat.p_cam = Eigen::Vector3f(0.1f, 0.2f, 1.5f);
      kf.features.push_back(feat);
      if (variant == 1) {
        kf.descriptors.type = "BRIEF-256";
        kf.descriptors.bytes_per_descriptor = 32;
        kf.descriptors.keypoints_uv.emplace_back(3.0f, 4.0f);
        kf.descriptors.keypoints_p_cam.emplace_back(0.1f, 0.2f, 1.5f);
        kf.descriptors.data.assign(32, 0xA5);
      }
      MapPoint p;
      p.p_cam = Eigen::Vector3f(0.1f, 0.2f, 1.5f);
      p.rgb = Rgb{10, 20, 30};
      kf.points.push_back(p);
      store.add(kf);
    }
    const std::string path = dir + "/k" + std::to_string(variant) + ".bin";
    store.save(path);
    seeds.push_back(readFileBytes(path));
  }
  std::filesystem::remove_all(dir);
  return seeds;
}

}  // namespace rgbdi::fuzz
