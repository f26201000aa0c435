// Benchmark of the saved map directory (saveMap / loadMap): for 1 000 and 5 000 synthetic
// keyframes of realistic size (per place: 400 ORB descriptors with keypoints and depth-backed
// points, 80 % with depth; per store keyframe: 150 tracked features, 300 kept map points;
// a loop edge every 25 keyframes) it prints the wall-clock time of a save (fsync included) and
// of a load (checksums and every consistency check included), and the size of every file.
// Without --keep the map is written under $TMPDIR and removed.
//
//   bench_map_io [--sizes N,N,...] [--dir DIR] [--repeat N] [--keep]
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/map/map_directory.h"

using namespace rgbdi;

namespace {

constexpr int kDescriptors = 400;
constexpr int kFeatures = 150;
constexpr int kPoints = 300;
constexpr int kLoopEvery = 25;

Eigen::Isometry3d poseAlongPath(double s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const double yaw = s / 5.0;
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(5.0 * std::cos(yaw), 5.0 * std::sin(yaw), 0.3);
  return T;
}

map::MapData syntheticMap(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::uniform_int_distribution<int> byte(0, 255);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  map::MapData m;
  m.manifest.camera = {640, 480, 615.0, 615.0, 320.0, 240.0, {0, 0, 0, 0, 0}};
  m.manifest.descriptor_type = "ORB-256";
  m.manifest.descriptor_bytes = 32;
  m.manifest.next_keyframe_id = static_cast<std::uint64_t>(n);
  m.manifest.next_segment = 1;
  m.manifest.sessions = 1;
  for (int i = 0; i < n; ++i) {
    const double s = 0.2 * i;
    loop::LoopKeyframe p;
    p.id = static_cast<std::uint64_t>(i);
    p.t = 0.1 * i;
    p.T_world_body_odom = poseAlongPath(s);
    p.T_world_body = poseAlongPath(s);
    p.travelled_m = s;
    mapping::DescriptorSet& d = p.descriptors;
    d.type = "ORB-256";
    d.bytes_per_descriptor = 32;
    d.data.resize(static_cast<std::size_t>(kDescriptors) * 32);
    for (auto& b : d.data) b = static_cast<std::uint8_t>(byte(rng));
    for (int k = 0; k < kDescriptors; ++k) {
      d.keypoints_uv.emplace_back(320 + 300 * u(rng), 240 + 220 * u(rng));
      d.keypoints_p_cam.push_back(k % 5 == 0 ? Eigen::Vector3f(nan, nan, nan)
                                             : Eigen::Vector3f(u(rng), u(rng), 3 + 2 * u(rng)));
    }
    m.places.push_back(std::move(p));

    mapping::Keyframe kf;
    kf.id = static_cast<std::uint64_t>(i);
    kf.frame_index = 3 * static_cast<std::uint64_t>(i);
    kf.t = 0.1 * i;
    kf.T_world_cam = poseAlongPath(s);
    for (int f = 0; f < kFeatures; ++f) {
      mapping::KeyframeFeature fe;
      fe.id = static_cast<std::uint64_t>(i * 40 + f);
      fe.uv = Eigen::Vector2d(320 + 300 * u(rng), 240 + 220 * u(rng)).cast<float>();
      fe.has_position = f % 4 != 0;
      if (fe.has_position) fe.p_cam = Eigen::Vector3d(u(rng), u(rng), 3 + 2 * u(rng)).cast<float>();
      kf.features.push_back(fe);
    }
    for (int q = 0; q < kPoints; ++q) {
      mapping::MapPoint mp;
      mp.p_cam = Eigen::Vector3f(u(rng), u(rng), 3 + 2 * u(rng));
      mp.rgb = {static_cast<std::uint8_t>(byte(rng)), 100, 50};
      kf.points.push_back(mp);
    }
    m.keyframes.add(std::move(kf));
    if (i >= 100 && i % kLoopEvery == 0) {
      map::MapLoopEdge e;
      e.from_id = static_cast<std::uint64_t>(i - 100);
      e.to_id = static_cast<std::uint64_t>(i);
      m.loops.push_back(e);
    }
  }
  return m;
}

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {1000, 5000};
  std::string base = std::filesystem::temp_directory_path().string();
  int repeat = 3;
  bool keep = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::stringstream ss(argv[++i]);
      for (std::string t; std::getline(ss, t, ',');) sizes.push_back(std::stoi(t));
    } else if (a == "--dir" && i + 1 < argc) {
      base = argv[++i];
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--keep") {
      keep = true;
    } else {
      std::fprintf(stderr,
                   "usage: bench_map_io [--sizes N,N,...] [--dir DIR] [--repeat N] [--keep]\n");
      return 2;
    }
  }
  const std::string root = base + "/bench_map_io." + std::to_string(::getpid());
  std::filesystem::create_directories(root);
  std::printf("map directory I/O (wall clock, best of %d; save includes fsync of every file)\n",
              repeat);
  std::printf("%10s %10s %10s %12s %12s %12s %12s\n", "keyframes", "save [s]", "load [s]",
              "total [MB]", "places [MB]", "store [MB]", "other [MB]");
  for (int n : sizes) {
    const map::MapData m = syntheticMap(n, 7);
    const std::string dir = root + "/map" + std::to_string(n);
    double save_s = 1e30, load_s = 1e30;
    for (int r = 0; r < repeat; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      map::saveMap(dir, m);
      save_s = std::min(save_s, seconds(t0));
      t0 = std::chrono::steady_clock::now();
      const map::MapData back = map::loadMap(dir);
      load_s = std::min(load_s, seconds(t0));
      if (back.places.size() != m.places.size() || back.keyframes.size() != m.keyframes.size()) {
        std::fprintf(stderr, "round trip lost keyframes\n");
        return 1;
      }
    }
    double total = 0, places = 0, store = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
      const double mb = static_cast<double>(e.file_size()) / 1e6;
      total += mb;
      if (e.path().filename() == map::kPlacesFile) places = mb;
      if (e.path().filename() == map::kKeyframesFile) store = mb;
    }
    std::printf("%10d %10.3f %10.3f %12.1f %12.1f %12.1f %12.2f\n", n, save_s, load_s, total,
                places, store, total - places - store);
  }
  if (!keep) std::filesystem::remove_all(root);
  return 0;
}
