// Place-recognition costs: ORB feature extraction per 640x480 keyframe, PlaceRecognizer::process
// (index query + proximity search + add) with 1 000 and 10 000 keyframes in the index, and the
// memory per keyframe (index postings and the descriptor set itself).
//
//   bench_loop_query [--frames N] [--queries N] [--flip P] [--seed N]
//
// Feature extraction runs on N rendered wheeled_circle frames (default noise, one every 0.5 s).
// The databases are built from those real descriptor sets, each copy with every descriptor bit
// flipped with probability P (default 0.1, so copies share few keys and the ORB bit statistics
// stay real), at random positions in a 50 m x 50 m area; the queries are the real sets. Timings
// are CPU time of the thread (steadier than wall time on a shared machine) and wall time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "rgbdi/loop/loop_features.h"
#include "rgbdi/loop/place_recognizer.h"
#include "rgbdi/sim/sequence.h"

using namespace rgbdi;

namespace {

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Timing {
  std::vector<double> cpu_ms, wall_ms;
  void add(double cpu_s, double wall_s) {
    cpu_ms.push_back(1e3 * cpu_s);
    wall_ms.push_back(1e3 * wall_s);
  }
  static double mean(const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return v.empty() ? 0.0 : s / static_cast<double>(v.size());
  }
  static double max(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
  }
};

mapping::DescriptorSet perturbed(const mapping::DescriptorSet& base, double flip,
                                 std::mt19937_64& rng) {
  mapping::DescriptorSet d = base;
  // Bernoulli(flip) per bit from raw generator output (portable, deterministic).
  const std::uint64_t threshold = static_cast<std::uint64_t>(flip * 18446744073709551615.0);
  for (std::uint8_t& byte : d.data)
    for (int b = 0; b < 8; ++b)
      if (rng() < threshold) byte ^= static_cast<std::uint8_t>(1u << b);
  return d;
}

void usage() {
  std::cerr << "usage: bench_loop_query [--frames N] [--queries N] [--flip P] [--seed N]\n";
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 60, queries = 200;
  double flip = 0.1;
  std::uint64_t seed = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) {
      usage();
      return 2;
    }
    if (a == "--frames")
      frames = std::stoi(argv[++i]);
    else if (a == "--queries")
      queries = std::stoi(argv[++i]);
    else if (a == "--flip")
      flip = std::stod(argv[++i]);
    else if (a == "--seed")
      seed = std::stoull(argv[++i]);
    else {
      usage();
      return 2;
    }
  }
  if (frames < 1 || queries < 1 || !(flip >= 0.0 && flip <= 0.5)) {
    usage();
    return 2;
  }

  auto ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::ProfileKind::WheeledCircle;
  so.prefetch_frames = false;
  sim::SimulatedSequence seq(so);
  const std::size_t step = static_cast<std::size_t>(std::lround(0.5 * so.fps));

  const loop::LoopFeatureOptions fo;
  loop::LoopFeatureExtractor extractor(fo);
  std::vector<mapping::DescriptorSet> real;
  Timing extraction;
  std::size_t keypoints = 0, with_point = 0;
  for (int k = 0; k < frames; ++k) {
    const std::size_t i = (static_cast<std::size_t>(k) * step) % seq.frameCount();
    const RgbdFrame frame = seq.renderFrame(i);
    const double c0 = threadCpuSeconds(), w0 = wallSeconds();
    real.push_back(extractor.extract(frame, frame.cam_color));
    extraction.add(threadCpuSeconds() - c0, wallSeconds() - w0);
    keypoints += real.back().size();
    for (std::size_t p = 0; p < real.back().size(); ++p) with_point += real.back().hasPoint(p);
  }
  const double mean_kp = static_cast<double>(keypoints) / frames;
  std::size_t descriptor_bytes = 0;
  for (const mapping::DescriptorSet& d : real)
    descriptor_bytes += sizeof(d) + d.type.capacity() + d.data.capacity() +
                        d.keypoints_uv.capacity() * sizeof(Eigen::Vector2f) +
                        d.keypoints_p_cam.capacity() * sizeof(Eigen::Vector3f);

  std::cout << std::fixed << std::setprecision(3);
  std::cout << "loop features (" << frames << " rendered " << so.camera.camera.width << "x"
            << so.camera.camera.height << " frames, max " << fo.max_keypoints
            << " keypoints): " << std::setprecision(1) << mean_kp << " keypoints, "
            << 100.0 * static_cast<double>(with_point) / static_cast<double>(keypoints)
            << " % with a 3-D point\n"
            << std::setprecision(3) << "  extraction ms/frame: cpu mean "
            << Timing::mean(extraction.cpu_ms) << " max " << Timing::max(extraction.cpu_ms)
            << ", wall mean " << Timing::mean(extraction.wall_ms) << "\n\n";

  const loop::PlaceRecognitionOptions po;
  std::cout << "| keyframes in index | process ms cpu mean | cpu max | wall mean | candidates "
               "per query | index bytes/keyframe | descriptor set bytes/keyframe |\n"
               "|---|---|---|---|---|---|---|\n";
  for (const std::size_t n : {std::size_t{1000}, std::size_t{10000}}) {
    std::mt19937_64 rng(seed);
    loop::PlaceRecognizer rec(po);
    // Positions only need to be spread out: a standard distribution is good enough here.
    std::uniform_real_distribution<double> where(0.0, 50.0);
    for (std::size_t k = 0; k < n; ++k) {
      loop::LoopKeyframe kf;
      kf.id = k;
      kf.t = static_cast<double>(k);
      kf.travelled_m = 0.5 * static_cast<double>(k);
      kf.T_world_body.translation() = Eigen::Vector3d(where(rng), where(rng), 0.0);
      kf.descriptors = perturbed(real[k % real.size()], flip, rng);
      rec.insert(kf);
    }
    const std::size_t bytes_before = rec.memoryBytes();
    Timing t;
    std::size_t candidates = 0;
    for (int q = 0; q < queries; ++q) {
      loop::LoopKeyframe kf;
      kf.id = n + static_cast<std::size_t>(q);
      kf.t = static_cast<double>(kf.id);
      kf.travelled_m = 0.5 * static_cast<double>(kf.id);
      kf.T_world_body.translation() = Eigen::Vector3d(where(rng), where(rng), 0.0);
      kf.descriptors = real[static_cast<std::size_t>(q) % real.size()];
      const double c0 = threadCpuSeconds(), w0 = wallSeconds();
      candidates += rec.process(kf).size();
      t.add(threadCpuSeconds() - c0, wallSeconds() - w0);
    }
    std::cout << "| " << n << " | " << Timing::mean(t.cpu_ms) << " | " << Timing::max(t.cpu_ms)
              << " | " << Timing::mean(t.wall_ms) << " | " << std::setprecision(2)
              << static_cast<double>(candidates) / queries << " | " << std::setprecision(0)
              << static_cast<double>(bytes_before) / static_cast<double>(n) << " | "
              << static_cast<double>(descriptor_bytes) / frames << " |\n"
              << std::setprecision(3);
  }
  std::cout << "\nindex: " << po.index.tables << " tables x " << po.index.key_bits
            << " bits; bytes/keyframe include the fixed table of "
            << (static_cast<std::size_t>(po.index.tables) << po.index.key_bits)
            << " posting lists divided by the keyframe count\n";
  return 0;
}
