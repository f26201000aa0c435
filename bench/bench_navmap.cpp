// Cost and size of the navigation maps (doc/navigation-maps.md "Speed and size"): builds them
// from synthetic maps of 1 and 5 million points (a square room, 12 m by default: floor, ceiling,
// walls, 16 boxes, 1 cm height noise) and a circle of path poses of a third of the room's side
// in radius, the same full build a run does at its end and a live run after a loop correction,
// and writes every file to measure its size. Then the incremental update of a live run
// (NavMapUpdater) in the same map: adding one keyframe's points (--keyframe-points, a D435-like
// keyframe: floor and a box in a 3 m x 2.5 m patch ahead of a path pose) and deriving the
// layers for the path, averaged over --keyframes keyframes along the path.
//
//   bench_navmap [--points N,N,...] [--poses N] [--room-m SIDE] [--repeat N] [--out DIR]
//                [--keyframe-points N] [--keyframes N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/navmap/nav_map_updater.h"
#include "rgbdi/navmap/navmap_files.h"

namespace {

using Clock = std::chrono::steady_clock;
double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

std::vector<Eigen::Vector3f> syntheticMap(std::size_t n, std::uint32_t seed, float side) {
  std::mt19937 rng(seed);
  const float half = 0.5f * side;
  std::uniform_real_distribution<float> u(-half, half), h(0.0f, 2.5f), unit(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  std::vector<Eigen::Vector3f> p;
  p.reserve(n);
  while (p.size() < n) {
    const float kind = unit(rng);
    if (kind < 0.55f) {  // floor
      p.emplace_back(u(rng), u(rng), noise(rng));
    } else if (kind < 0.65f) {  // ceiling
      p.emplace_back(u(rng), u(rng), 2.5f + noise(rng));
    } else if (kind < 0.85f) {  // walls
      const float s = u(rng), wall = unit(rng) < 0.5f ? -half : half;
      if (unit(rng) < 0.5f)
        p.emplace_back(wall + noise(rng), s, h(rng));
      else
        p.emplace_back(s, wall + noise(rng), h(rng));
    } else {  // 16 boxes 0.5 m wide, 0.6 m high, along the room's inner ring
      const int b = static_cast<int>(unit(rng) * 16) % 16;
      const float a = static_cast<float>(b) * 0.3927f;
      const float cx = 0.42f * side * std::cos(a), cy = 0.42f * side * std::sin(a);
      p.emplace_back(cx + 0.5f * (unit(rng) - 0.5f), cy + 0.5f * (unit(rng) - 0.5f),
                     0.6f * unit(rng) + noise(rng));
    }
  }
  return p;
}

/// A keyframe's points: floor (80 %) and a 0.4 m box (20 %) in a 3 m x 2.5 m patch ahead of
/// (x, y) in the direction a, 1 cm height noise.
std::vector<Eigen::Vector3f> keyframePoints(std::size_t n, std::uint32_t seed, double x, double y,
                                            double a) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> fwd(0.3f, 3.3f), side(-1.25f, 1.25f), unit(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  const float c = static_cast<float>(std::cos(a)), s = static_cast<float>(std::sin(a));
  std::vector<Eigen::Vector3f> p;
  p.reserve(n);
  while (p.size() < n) {
    const bool box = unit(rng) < 0.2f;
    const float f = box ? 2.0f + 0.4f * unit(rng) : fwd(rng);
    const float l = box ? 0.4f * unit(rng) : side(rng);
    const float z = box ? 0.4f * unit(rng) : noise(rng);
    p.emplace_back(static_cast<float>(x) + c * f - s * l, static_cast<float>(y) + s * f + c * l, z);
  }
  return p;
}

std::vector<std::size_t> parseCounts(const std::string& text) {
  std::vector<std::size_t> out;
  std::stringstream ss(text);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stoul(item));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> counts{1000000, 5000000};
  std::size_t poses = 2000;
  int repeat = 3;
  double room = 12.0;
  std::string out = "/tmp/bench_navmap";
  std::size_t keyframe_points = 15000;
  int keyframes = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--points")
      counts = parseCounts(v);
    else if (a == "--poses")
      poses = std::stoul(v);
    else if (a == "--repeat")
      repeat = std::max(1, std::stoi(v));
    else if (a == "--room-m")
      room = std::max(2.0, std::stod(v));
    else if (a == "--out")
      out = v;
    else if (a == "--keyframe-points")
      keyframe_points = std::stoul(v);
    else if (a == "--keyframes")
      keyframes = std::max(1, std::stoi(v));
    else {
      std::cerr
          << "usage: bench_navmap [--points N,N,...] [--poses N] [--room-m SIDE] [--repeat N] "
             "[--out DIR] [--keyframe-points N] [--keyframes N]\n";
      return 2;
    }
  }
  std::filesystem::create_directories(out);
  std::vector<Eigen::Vector3d> path;
  for (std::size_t k = 0; k < poses; ++k) {
    const double a = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(poses);
    path.emplace_back(room / 3.0 * std::cos(a), room / 3.0 * std::sin(a), 0.3);
  }
  const rgbdi::navmap::NavMapOptions options;
  std::cout << "points     build_ms(min of " << repeat
            << ")  write_ms  cells     free     occupied  files_bytes\n";
  for (std::size_t n : counts) {
    const std::vector<Eigen::Vector3f> points = syntheticMap(n, 7, static_cast<float>(room));
    double best = 1e300;
    rgbdi::navmap::NavMap map;
    for (int r = 0; r < repeat; ++r) {
      const auto t0 = Clock::now();
      map = rgbdi::navmap::buildNavMap(points, path, options);
      best = std::min(best, ms(t0, Clock::now()));
    }
    const auto w0 = Clock::now();
    const auto files = rgbdi::navmap::writeNavMapFiles(map, out, &path);
    const double write_ms = ms(w0, Clock::now());
    std::uintmax_t bytes = 0;
    for (const auto& f : files) bytes += std::filesystem::file_size(f.second);
    const std::size_t free = map.count(rgbdi::navmap::CellState::kFree);
    const std::size_t unknown = map.count(rgbdi::navmap::CellState::kUnknown);
    std::cout << std::left << std::setw(11) << n << std::setw(22) << std::fixed
              << std::setprecision(1) << best << std::setw(10) << write_ms << std::setw(10)
              << map.grid.cellCount() << std::setw(9) << free << std::setw(10)
              << map.grid.cellCount() - free - unknown << bytes << "\n";
    for (const auto& f : files)
      std::cout << "  " << f.second << " " << std::filesystem::file_size(f.second) << " bytes\n";
  }
  // Incremental: the updater holds the map; each keyframe adds its points and the layers are
  // derived for the path (a live refresh between loop corrections).
  std::cout << "\nincremental, keyframes of " << keyframe_points << " points (mean of " << keyframes
            << "):\npoints     fill_ms   add_ms  derive_ms  update_ms  full_ms\n";
  for (std::size_t n : counts) {
    const std::vector<Eigen::Vector3f> points = syntheticMap(n, 7, static_cast<float>(room));
    rgbdi::navmap::NavMapUpdater updater(options);
    const auto f0 = Clock::now();
    updater.addPoints(points);
    const double fill_ms = ms(f0, Clock::now());
    double add = 0.0, derive = 0.0, full = 0.0;
    std::vector<Eigen::Vector3f> all = points;
    for (int k = 0; k < keyframes; ++k) {
      const std::size_t at =
          static_cast<std::size_t>(k) * poses / static_cast<std::size_t>(keyframes);
      const double a = 2.0 * M_PI * static_cast<double>(at) / static_cast<double>(poses);
      const std::vector<Eigen::Vector3f> kf =
          keyframePoints(keyframe_points, 100 + static_cast<std::uint32_t>(k), path[at].x(),
                         path[at].y(), a + 0.5 * M_PI);
      const auto t0 = Clock::now();
      updater.addPoints(kf);
      const auto t1 = Clock::now();
      const rgbdi::navmap::NavMap inc = updater.build(path);
      const auto t2 = Clock::now();
      add += ms(t0, t1);
      derive += ms(t1, t2);
      all.insert(all.end(), kf.begin(), kf.end());
      if (k == 0) {  // one full build for comparison (and to check the two agree)
        const auto t3 = Clock::now();
        const rgbdi::navmap::NavMap f = rgbdi::navmap::buildNavMap(all, path, options);
        full = ms(t3, Clock::now());
        if (f.state != inc.state || f.traversability.size() != inc.traversability.size()) {
          std::cerr << "incremental and full build differ\n";
          return 1;
        }
      }
    }
    std::cout << std::left << std::setw(11) << n << std::setw(10) << fill_ms << std::setw(8)
              << add / keyframes << std::setw(11) << derive / keyframes << std::setw(11)
              << (add + derive) / keyframes << full << "\n";
  }
  return 0;
}
