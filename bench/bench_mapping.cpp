// Reproduction of the paper's Table 2 (efficiency of the octree structure) plus mapping costs:
// number of map points without filter ("origin") and with leaf capacity 5, 3 and 1, the time to
// rebuild the map after a pose update ("loop cost"), the points kept by the >= 3 leaf filter,
// insertion and occupancy ray-casting time per keyframe, and memory.
//
//   bench_mapping [--profile NAME] [--duration S] [--fps N] [--seed N]   (simulated, in-process)
//   bench_mapping --rawlog FILE --trajectory TUM [--trajectory-frame camera|body] [--config INI]
//   common: [--keyframe-distance M] [--keyframe-angle DEG] [--resolution M]
//           [--correction-m M] [--correction-deg DEG] [--no-occupancy]
//   common: [--loop-update]  also times PointMap::update after loops moving the newest 10 %, 50 %
//           and 100 % of the keyframes (correction growing from 0 to --correction-m /
//           --correction-deg across the moved ones, keyframes under [mapping]
//           correction_min_* left alone, as Mapper::correct does) against a full rebuild
//   common: [--save-keyframes FILE]  writes the capacity-5 keyframes (KeyframeStore::save)
//   bench_mapping --loop-update-from FILE [--correction-m M] [--correction-deg DEG]
//                                  only the --loop-update table, on keyframes saved that way
//   bench_mapping --fixed-inputs   the per-keyframe figures on the fixed synthetic frames that the
//                                  unit tests use (they asserted wall time until issue 14)
//
// Keyframes are taken whenever the camera moved --keyframe-distance or turned --keyframe-angle
// since the last one. The pose update applied before the rebuild is a loop-closure-like
// correction growing linearly from zero at the first keyframe to --correction-m (translation)
// and --correction-deg (yaw about the vertical) at the last.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "../tests/mapping/synthetic_frames.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/stream_options.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "rgbdi/sim/sequence.h"

using namespace rgbdi;

namespace {

struct Args {
  std::string profile = "wheeled_circle";
  double duration = 0.0, fps = 30.0;
  std::uint64_t seed = 1;
  std::string rawlog, trajectory, trajectory_frame = "camera", config;
  double keyframe_distance = 0.2, keyframe_angle_deg = 10.0, resolution = 0.0;
  double correction_m = 0.3, correction_deg = 3.0;
  bool occupancy = true;
  bool loop_update = false;
  std::string save_keyframes, loop_update_from;
};

constexpr int kRebuildRepeats = 3;

/// CPU time of the calling thread [s]: on a shared, loaded machine it is far steadier than
/// wall-clock time.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double ms(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double, std::milli>(d).count();
}

/// One point map configuration of the table and its keyframes.
struct Variant {
  std::string name;
  mapping::PointMap map;
  mapping::KeyframeStore store;
  std::vector<double> insert_ms;
  Variant(std::string n, const mapping::MappingOptions& o) : name(std::move(n)), map(o) {}
};

class KeyframeSelector {
 public:
  KeyframeSelector(double distance, double angle_rad) : distance_(distance), angle_(angle_rad) {}
  bool accept(const Eigen::Isometry3d& T) {
    if (last_) {
      const Eigen::Isometry3d d = last_->inverse() * T;
      if (d.translation().norm() < distance_ && Eigen::AngleAxisd(d.rotation()).angle() < angle_)
        return false;
    }
    last_ = T;
    return true;
  }

 private:
  double distance_, angle_;
  std::optional<Eigen::Isometry3d> last_;
};

/// Map update after a loop (PointMap::update) vs a full rebuild, per million map points, on
/// the capacity-5 keyframes (`source`) with the configured isolated-leaf rule.
void reportLoopUpdate(const Args& args_, const mapping::MappingOptions& base_,
                      const mapping::KeyframeStore& source) {
  const std::size_t n = source.size();
  std::cout << "\nmap update after a loop (capacity " << base_.max_points_per_leaf
            << ", isolated-leaf rule " << base_.min_points_per_leaf_rebuild
            << ", thread CPU time, minimum of " << kRebuildRepeats << ")\n";
  std::cout << "| moved keyframes | moved points | map points | update [ms] | update [ms per M "
               "points] | full rebuild [ms] | rebuild [ms per M points] | same map |\n"
               "|---|---|---|---|---|---|---|---|\n";
  const double min_cos_half = std::cos(0.5 * base_.correction_min_rotation_deg * M_PI / 180.0);
  for (const double share : {0.1, 0.5, 1.0}) {
    const std::size_t first = n - static_cast<std::size_t>(std::lround(share * n));
    double update_ms = std::numeric_limits<double>::infinity(), rebuild_ms = update_ms;
    std::size_t moved_kf = 0, moved_points = 0, map_points = 0;
    bool same = true;
    for (int repeat = 0; repeat < kRebuildRepeats; ++repeat) {
      // Two identical maps as a run has them: every keyframe inserted, the isolated-leaf rule
      // applied once (an earlier loop).
      mapping::PointMap a(base_), b(base_);
      mapping::KeyframeStore sa, sb;
      for (const mapping::Keyframe& kf : source.keyframes()) {
        mapping::Keyframe k = kf;
        k.points = a.insertPoints(kf.points, kf.T_world_cam, kf.id);
        sa.add(k);
        k.points = b.insertPoints(kf.points, kf.T_world_cam, kf.id);
        sb.add(k);
      }
      a.update(sa, {});
      b.update(sb, {});
      map_points = a.pointCount();
      std::vector<std::uint64_t> moved;
      moved_points = 0;
      const double dyaw = args_.correction_deg * M_PI / 180.0;
      for (std::size_t k = first; k < n; ++k) {
        const double f = n - first > 1
                             ? static_cast<double>(k - first) / static_cast<double>(n - 1 - first)
                             : 1.0;
        Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
        C.linear() = Eigen::AngleAxisd(f * dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        C.translation() = f * args_.correction_m * Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
        const mapping::Keyframe& kf = sa.at(k);
        const Eigen::Isometry3d T = C * kf.T_world_cam;
        const double cos_half = std::abs(
            Eigen::Quaterniond(kf.T_world_cam.rotation()).dot(Eigen::Quaterniond(T.rotation())));
        if ((T.translation() - kf.T_world_cam.translation()).norm() <
                base_.correction_min_shift_m &&
            cos_half > min_cos_half)
          continue;
        moved_points += kf.points.size();
        sa.setPose(kf.id, T);
        sb.setPose(kf.id, T);
        moved.push_back(kf.id);
      }
      moved_kf = moved.size();
      double cpu0 = threadCpuSeconds();
      const mapping::RebuildReport ra = a.update(sa, moved);
      update_ms = std::min(update_ms, 1e3 * (threadCpuSeconds() - cpu0));
      cpu0 = threadCpuSeconds();
      const mapping::RebuildReport rb = b.rebuild(sb);
      rebuild_ms = std::min(rebuild_ms, 1e3 * (threadCpuSeconds() - cpu0));
      same = same && ra.kept_points == rb.kept_points && a.leafCount() == b.leafCount() &&
             ra.sparse_points_removed == rb.sparse_points_removed &&
             ra.rejected_full_leaf == rb.rejected_full_leaf;
    }
    const double per_m = 1e6 / static_cast<double>(std::max<std::size_t>(map_points, 1));
    std::cout << std::fixed << std::setprecision(1) << "| " << moved_kf << " of " << n << " ("
              << 100.0 * share << " %) | " << moved_points << " | " << map_points << " | "
              << update_ms << " | " << update_ms * per_m << " | " << rebuild_ms << " | "
              << rebuild_ms * per_m << " | " << (same ? "yes" : "NO") << " |\n";
  }
  // What the map and the keyframes behind it hold (capacity-based estimates, as summary.json).
  mapping::PointMap map(base_);
  mapping::KeyframeStore store;
  for (const mapping::Keyframe& kf : source.keyframes()) {
    mapping::Keyframe k = kf;
    k.points = map.insertPoints(kf.points, kf.T_world_cam, kf.id);
    store.add(std::move(k));
  }
  map.update(store, {});
  std::cout << std::setprecision(1) << "memory: map " << map.memoryBytes() / 1048576.0 << " MiB, "
            << static_cast<double>(map.memoryBytes()) /
                   static_cast<double>(std::max<std::size_t>(map.pointCount(), 1))
            << " B per point (" << map.pointCount() << " points, " << map.leafCount()
            << " leaves); keyframe store "
            << static_cast<double>(store.memoryBytes()) / static_cast<double>(store.size())
            << " B per keyframe (record " << sizeof(mapping::Keyframe) << " B, "
            << sizeof(mapping::MapPoint) << " B per kept point, "
            << sizeof(mapping::KeyframeFeature)
            << " B per feature; these keyframes carry no features)\n";
}

class Bench {
 public:
  Bench(const Args& a, const mapping::MappingOptions& base) : args_(a), base_(base) {
    mapping::MappingOptions o = base;
    o.max_points_per_leaf = 1000000;  // no capacity filter: the paper's "origin"
    o.min_points_per_leaf_rebuild = 0;
    variants_.push_back(std::make_unique<Variant>("no filter", o));
    for (int capacity : {5, 3, 1}) {
      o = base;
      o.max_points_per_leaf = capacity;
      o.min_points_per_leaf_rebuild = 0;  // as in the paper's table: no filter after the update
      variants_.push_back(std::make_unique<Variant>("capacity " + std::to_string(capacity), o));
    }
    if (a.occupancy) {
      occupancy_ = std::make_unique<mapping::OccupancyMap>(base);
      // rgbdi-slam's path: the keyframe's kept points (capacity 5), once with a ray through
      // every point and once with the configured share of rays.
      mapping::MappingOptions every_ray = base;
      every_ray.occupancy_grid_stride = 1;
      kept_all_rays_ = std::make_unique<mapping::OccupancyMap>(every_ray);
      kept_strided_ = std::make_unique<mapping::OccupancyMap>(base);
    }
  }

  void addKeyframe(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam) {
    for (auto& v : variants_) {
      mapping::Keyframe kf;
      kf.id = next_id_;
      kf.t = frame.t;
      kf.frame_index = frame.index;
      kf.T_world_cam = T_world_cam;
      const auto t0 = std::chrono::steady_clock::now();
      kf.points = v->map.insertKeyframe(frame, T_world_cam);
      v->insert_ms.push_back(ms(std::chrono::steady_clock::now() - t0));
      v->store.add(std::move(kf));
    }
    if (occupancy_) {
      occupancy_->insert(frame, T_world_cam);
      const auto& kept = variants_[1]->store.keyframes().back().points;
      double t0 = threadCpuSeconds();
      kept_all_rays_->insertPoints(kept, T_world_cam);
      kept_all_rays_cpu_s_ += threadCpuSeconds() - t0;
      t0 = threadCpuSeconds();
      kept_strided_->insertPoints(kept, T_world_cam);
      kept_strided_cpu_s_ += threadCpuSeconds() - t0;
    }
    ++next_id_;
  }

  void report(const std::string& scene) {
    const std::size_t n = next_id_;
    if (n == 0) throw std::runtime_error("no keyframe was selected");
    if (!args_.save_keyframes.empty()) variants_[1]->store.save(args_.save_keyframes);
    if (args_.loop_update) reportLoopUpdate(args_, base_, variants_[1]->store);
    // Loop-closure-like correction, growing along the keyframes.
    const double dyaw = args_.correction_deg * M_PI / 180.0;
    std::vector<double> rebuild_ms(variants_.size()), rebuild_cpu_ms(variants_.size());
    std::vector<std::size_t> rebuilt_points(variants_.size());
    for (std::size_t i = 0; i < variants_.size(); ++i) {
      Variant& v = *variants_[i];
      for (std::size_t k = 0; k < n; ++k) {
        const double f = n > 1 ? static_cast<double>(k) / static_cast<double>(n - 1) : 0.0;
        Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
        C.linear() = Eigen::AngleAxisd(f * dyaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        C.translation() = f * args_.correction_m * Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
        v.store.setPose(k, C * v.store.get(k).T_world_cam);
      }
      // The first rebuild applies the update; repeating it (same poses, nothing dropped since
      // min_points_per_leaf_rebuild = 0) gives the same map: the minimum of the times is
      // reported, the machine being shared.
      rebuild_ms[i] = rebuild_cpu_ms[i] = std::numeric_limits<double>::infinity();
      for (int repeat = 0; repeat < kRebuildRepeats; ++repeat) {
        const double cpu0 = threadCpuSeconds();
        const mapping::RebuildReport r = v.map.rebuild(v.store);
        rebuild_cpu_ms[i] = std::min(rebuild_cpu_ms[i], 1e3 * (threadCpuSeconds() - cpu0));
        rebuild_ms[i] = std::min(rebuild_ms[i], 1e3 * r.seconds);
        rebuilt_points[i] = r.kept_points;
      }
    }
    // The paper's clean-up: rebuild of the capacity-5 map dropping leaves with < 3 points.
    mapping::MappingOptions filtered = base_;
    filtered.max_points_per_leaf = 5;
    filtered.min_points_per_leaf_rebuild = 3;
    mapping::PointMap cleaned(filtered);
    mapping::KeyframeStore store5 = variants_[1]->store;
    const mapping::RebuildReport clean = cleaned.rebuild(store5);

    const auto& st = variants_[0]->map.stats();
    const std::size_t origin = st.candidates;
    auto median = [](std::vector<double> x) {
      std::sort(x.begin(), x.end());
      return x[x.size() / 2];
    };
    std::cout << std::fixed << std::setprecision(1);
    std::cout << "\n"
              << scene << ": " << n << " keyframes, " << st.grid_points << " grid points, "
              << st.no_depth << " without depth, " << st.out_of_range << " outside ("
              << base_.depth_min_m << ", " << base_.depth_max_m << ") m\n\n";
    std::cout << std::setprecision(3) << "Table 2 | resolution " << base_.octree_resolution_m
              << " m, keyframe every " << args_.keyframe_distance << " m / "
              << args_.keyframe_angle_deg << " deg, pose update " << args_.correction_m << " m / "
              << args_.correction_deg << " deg\n"
              << std::setprecision(1);
    std::cout << "  origin points        " << origin << "\n";
    for (std::size_t i = 1; i < variants_.size(); ++i)
      std::cout << "  octree " << variants_[i]->name
                << std::string(12 - variants_[i]->name.size(), ' ') << " "
                << variants_[i]->map.pointCount() << "  ("
                << 100.0 * variants_[i]->map.pointCount() / std::max<std::size_t>(origin, 1)
                << " % of origin)\n";
    const double speedup = 100.0 * (1.0 - static_cast<double>(variants_[1]->map.pointCount()) /
                                              std::max<std::size_t>(origin, 1));
    std::cout << std::setprecision(2);
    std::cout << "  loop cost 5 pts      " << rebuild_cpu_ms[1] << " ms CPU, " << rebuild_ms[1]
              << " ms wall  (no filter: " << rebuild_cpu_ms[0]
              << " ms CPU; capacity 3: " << rebuild_cpu_ms[2]
              << "; capacity 1: " << rebuild_cpu_ms[3] << ")\n";
    std::cout << std::setprecision(1);
    std::cout << "  speed up (5 pts)     " << speedup << " % by point count, "
              << 100.0 * (1.0 - rebuild_cpu_ms[1] / std::max(rebuild_cpu_ms[0], 1e-9))
              << " % by measured CPU time\n";
    std::cout << "  after update, capacity 5 + drop leaves < 3: " << clean.kept_points
              << " points (" << clean.sparse_leaves_removed << " sparse leaves removed)\n\n";
    std::cout << std::setprecision(3);
    std::cout << "per keyframe: insert (capacity 5) median " << median(variants_[1]->insert_ms)
              << " ms, max "
              << *std::max_element(variants_[1]->insert_ms.begin(), variants_[1]->insert_ms.end())
              << " ms; no filter median " << median(variants_[0]->insert_ms) << " ms\n";
    if (occupancy_)
      std::cout << "occupancy (" << base_.occupancy_resolution_m << " m, grid stride "
                << base_.occupancy_grid_stride << "): " << occupancy_->stats().rays / n << " rays, "
                << 1e3 * occupancy_->stats().seconds / static_cast<double>(n)
                << " ms per keyframe, " << occupancy_->leafCount() << " leaves\n";
    if (occupancy_)
      std::cout << "occupancy from kept points (rgbdi-slam), CPU per keyframe: every point "
                << kept_all_rays_->stats().rays / n << " rays "
                << 1e3 * kept_all_rays_cpu_s_ / static_cast<double>(n) << " ms, "
                << kept_all_rays_->leafCount() << " leaves; every stride^2-th point "
                << kept_strided_->stats().rays / n << " rays "
                << 1e3 * kept_strided_cpu_s_ / static_cast<double>(n) << " ms, "
                << kept_strided_->leafCount() << " leaves\n";
    std::cout << std::setprecision(1);
    std::cout << "memory: map capacity 5 " << variants_[1]->map.memoryBytes() / 1048576.0
              << " MiB (" << variants_[1]->map.leafCount() << " leaves), keyframe store "
              << variants_[1]->store.memoryBytes() / 1048576.0 << " MiB; no filter map "
              << variants_[0]->map.memoryBytes() / 1048576.0 << " MiB, store "
              << variants_[0]->store.memoryBytes() / 1048576.0 << " MiB";
    if (occupancy_) std::cout << "; occupancy " << occupancy_->memoryBytes() / 1048576.0 << " MiB";
    std::cout << "\n";
  }

 private:
  const Args& args_;
  mapping::MappingOptions base_;
  std::vector<std::unique_ptr<Variant>> variants_;
  std::unique_ptr<mapping::OccupancyMap> occupancy_, kept_all_rays_, kept_strided_;
  double kept_all_rays_cpu_s_ = 0.0, kept_strided_cpu_s_ = 0.0;
  std::uint64_t next_id_ = 0;
};

void runSimulated(const Args& a, const mapping::MappingOptions& options) {
  IniReader ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::parseProfileKind(a.profile);
  so.profile.duration_s = a.duration;
  so.seed = a.seed;
  so.fps = a.fps;
  so.prefetch_frames = false;
  sim::SimulatedSequence seq(so);
  Bench bench(a, options);
  KeyframeSelector selector(a.keyframe_distance, a.keyframe_angle_deg * M_PI / 180.0);
  for (std::size_t i = 0; i < seq.frameCount(); ++i) {
    const Eigen::Isometry3d T = seq.cameraPose(seq.frameExposureTime(i));
    if (selector.accept(T)) bench.addKeyframe(seq.renderFrame(i), T);
  }
  bench.report("simulated " + a.profile + " (" + std::to_string(seq.duration()) + " s, " +
               std::to_string(seq.profile().path_length_m) + " m, seed " + std::to_string(a.seed) +
               ")");
}

/// Feeds the frames of a rawlog whose stamp has a trajectory pose (within 20 ms) to the bench.
class RawlogKeyframes : public MeasurementSink {
 public:
  RawlogKeyframes(Bench& bench, const Trajectory& traj, const Eigen::Isometry3d& T_pose_cam,
                  KeyframeSelector selector)
      : bench_(bench), traj_(traj), T_pose_cam_(T_pose_cam), selector_(selector) {}
  void feedImu(const ImuSample&) override {}
  void feedRgbd(const RgbdFrame& frame) override {
    const auto it = std::lower_bound(traj_.begin(), traj_.end(), frame.t,
                                     [](const StampedPose& s, double t) { return s.t < t; });
    const StampedPose* best = nullptr;
    for (auto c : {it, it == traj_.begin() ? traj_.end() : it - 1})
      if (c != traj_.end() && std::abs(c->t - frame.t) <= kMaxDt &&
          (!best || std::abs(c->t - frame.t) < std::abs(best->t - frame.t)))
        best = &*c;
    if (!best || !frame.hasDepth()) return;
    const Eigen::Isometry3d T = best->isometry() * T_pose_cam_;
    if (selector_.accept(T)) bench_.addKeyframe(frame, T);
  }

 private:
  static constexpr double kMaxDt = 0.02;  // [s] frame-to-pose association
  Bench& bench_;
  const Trajectory& traj_;
  Eigen::Isometry3d T_pose_cam_;
  KeyframeSelector selector_;
};

void runRawlog(const Args& a, IniReader& ini, const mapping::MappingOptions& options) {
  const io::StreamConfig stream = io::StreamConfig::load(ini);
  const Trajectory traj = eval::readTum(a.trajectory);
  const Eigen::Isometry3d T_pose_cam =
      a.trajectory_frame == "body" ? stream.extrinsic.T_body_cam : Eigen::Isometry3d::Identity();
  Bench bench(a, options);
  RawlogKeyframes sink(bench, traj, T_pose_cam,
                       KeyframeSelector(a.keyframe_distance, a.keyframe_angle_deg * M_PI / 180.0));
  io::RawlogSource source(a.rawlog, stream);
  source.pump(sink);
  bench.report(a.rawlog);
}

}  // namespace

/// Insertion and ray-casting time on fixed synthetic frames (a 640x480 plane with varied depth):
/// the figures tests/mapping once asserted (median insertKeyframe < 5 ms, ray casting < 100 ms).
void runFixedInputs() {
  using mapping::test::planeFrame;
  {
    mapping::PointMap map{mapping::MappingOptions{}};
    std::mt19937_64 rng(11);
    RgbdFrame f = planeFrame(2000);
    std::uniform_int_distribution<int> depth(500, 5000);
    for (int v = 0; v < f.depth.rows; ++v)
      for (int u = 0; u < f.depth.cols; ++u)
        f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(depth(rng));
    std::uniform_real_distribution<double> uni(-1.0, 1.0);
    std::vector<double> ms;
    for (int k = 0; k < 40; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      const Eigen::Vector3d axis = Eigen::Vector3d(uni(rng), uni(rng), uni(rng)).normalized();
      T.linear() = Eigen::AngleAxisd(3.0 * uni(rng), axis).toRotationMatrix();
      T.translation() = 2.0 * Eigen::Vector3d(uni(rng), uni(rng), uni(rng));
      const double t0 = threadCpuSeconds();
      map.insertKeyframe(f, T);
      ms.push_back(1e3 * (threadCpuSeconds() - t0));
    }
    std::sort(ms.begin(), ms.end());
    std::cout << "fixed input: PointMap::insertKeyframe, 40 random poses: median " << ms[20]
              << " ms, max " << ms.back() << " ms (CPU time)\n";
  }
  {
    mapping::OccupancyMap map{mapping::MappingOptions{}};
    RgbdFrame f = planeFrame(3000);
    for (int v = 0; v < f.depth.rows; ++v)
      for (int u = 0; u < f.depth.cols; ++u)
        f.depth.at<std::uint16_t>(v, u) =
            static_cast<std::uint16_t>(1500 + (u * 7 + v * 13) % 3000);
    const int n = 10;
    for (int k = 0; k < n; ++k) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = Eigen::Vector3d(0.05 * k, 0.0, 0.0);
      map.insert(f, T);
    }
    std::cout << "fixed input: OccupancyMap::insert, " << n
              << " keyframes: " << map.stats().rays / n << " rays/keyframe, "
              << 1e3 * map.stats().seconds / n << " ms/keyframe\n";
  }
}

int main(int argc, char** argv) {
  Args a;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
        return argv[++i];
      };
      if (arg == "--profile")
        a.profile = next();
      else if (arg == "--duration")
        a.duration = std::stod(next());
      else if (arg == "--fps")
        a.fps = std::stod(next());
      else if (arg == "--seed")
        a.seed = std::stoull(next());
      else if (arg == "--rawlog")
        a.rawlog = next();
      else if (arg == "--trajectory")
        a.trajectory = next();
      else if (arg == "--trajectory-frame")
        a.trajectory_frame = next();
      else if (arg == "--config")
        a.config = next();
      else if (arg == "--keyframe-distance")
        a.keyframe_distance = std::stod(next());
      else if (arg == "--keyframe-angle")
        a.keyframe_angle_deg = std::stod(next());
      else if (arg == "--resolution")
        a.resolution = std::stod(next());
      else if (arg == "--correction-m")
        a.correction_m = std::stod(next());
      else if (arg == "--correction-deg")
        a.correction_deg = std::stod(next());
      else if (arg == "--no-occupancy")
        a.occupancy = false;
      else if (arg == "--loop-update")
        a.loop_update = true;
      else if (arg == "--save-keyframes")
        a.save_keyframes = next();
      else if (arg == "--loop-update-from")
        a.loop_update_from = next();
      else if (arg == "--fixed-inputs") {
        runFixedInputs();
        return 0;
      } else
        throw std::invalid_argument("unknown argument " + arg);
    }
    if (a.rawlog.empty() != a.trajectory.empty())
      throw std::invalid_argument("--rawlog and --trajectory go together");
    if (a.trajectory_frame != "camera" && a.trajectory_frame != "body")
      throw std::invalid_argument("--trajectory-frame is camera or body");
    IniReader ini = a.config.empty() ? IniReader::empty() : IniReader::fromFile(a.config);
    mapping::MappingOptions options = mapping::MappingOptions::load(ini);
    if (a.resolution > 0.0) options.octree_resolution_m = a.resolution;
    if (!a.loop_update_from.empty()) {
      const mapping::KeyframeStore store = mapping::KeyframeStore::load(a.loop_update_from);
      std::cout << a.loop_update_from << ": " << store.size() << " keyframes, "
                << store.pointCount() << " kept points\n";
      reportLoopUpdate(a, options, store);
    } else if (a.rawlog.empty())
      runSimulated(a, options);
    else
      runRawlog(a, ini, options);
  } catch (const std::exception& e) {
    std::cerr << "bench_mapping: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
