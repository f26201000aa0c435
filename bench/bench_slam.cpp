// The whole SlamSystem, threaded, on a generated sequence: the odometry's per-frame latency with
// loop closing on and off (it must not grow while loops are detected and solved), memory per
// keyframe (keyframe store, loop-closure descriptors + place index + graph), accuracy, and how
// many points each lap added to the map.
//
//   bench_slam [--profile NAME] [--duration S] [--fps N] [--seed N]      (simulator in-process)
//   bench_slam --rawlog FILE --gt TUM --config INI [--profile NAME]      (a rgbdi-sim sequence;
//              --profile gives the lap length for the per-lap figures)
//   common: [--loop on|off|both] [--speed X] [--offline] [--dump PREFIX]
//
// --speed X feeds the measurements at X times real time (default 1: a robot's case; 0: as fast as
// the system takes them, then the latency is mostly queueing). Latency of a frame = from the
// moment feedRgbd returned (the frame is queued) to the moment the odometry finished it
// (SlamSystem::progress().frames, polled every 0.1 ms). By default the system runs in live mode
// (drift corrections taken when ready, as on a robot); --offline makes the odometry wait for
// loop closing at the defined points that keep offline runs deterministic.
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_system.h"

using namespace rgbdi;
using Clock = std::chrono::steady_clock;

namespace {

struct Args {
  std::string profile = "wheeled_circle";
  double duration = 0.0, fps = 15.0, speed = 1.0;
  std::uint64_t seed = 1;
  std::string rawlog, gt, config, loop = "both";
  std::string dump;  ///< prefix of the graph dump (--dump PREFIX), empty: none
  bool offline = false;
};

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Forwards measurements to the system at `speed` times their own pace and notes when each
/// frame was queued.
class PacedSink : public MeasurementSink {
 public:
  PacedSink(system::SlamSystem& sys, double speed, std::vector<double>& fed)
      : sys_(sys), speed_(speed), fed_(fed) {}
  void feedImu(const ImuSample& imu) override {
    pace(imu.t);
    sys_.feedImu(imu);
  }
  void feedWheel(const WheelOdometrySample& wheel) override {
    pace(wheel.t);
    sys_.feedWheel(wheel);
  }
  void feedRgbd(const RgbdFrame& frame) override {
    pace(frame.t);
    sys_.feedRgbd(frame);
    fed_.push_back(secondsSince(start_));
  }
  void endOfStream() override { sys_.endOfStream(); }
  Clock::time_point start() const { return start_; }

 private:
  void pace(double t) {
    if (!t0_) t0_ = t;
    if (speed_ <= 0.0) return;
    std::this_thread::sleep_until(start_ + std::chrono::duration_cast<Clock::duration>(
                                               std::chrono::duration<double>((t - *t0_) / speed_)));
  }
  system::SlamSystem& sys_;
  double speed_;
  std::vector<double>& fed_;
  std::optional<double> t0_;
  const Clock::time_point start_ = Clock::now();
};

struct Percentiles {
  double p50 = 0, p95 = 0, max = 0;
  std::size_t n = 0;
};

Percentiles percentiles(std::vector<double> v) {
  Percentiles p;
  p.n = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  p.p50 = v[v.size() / 2];
  p.p95 = v[std::min(v.size() - 1, static_cast<std::size_t>(0.95 * static_cast<double>(v.size())))];
  p.max = v.back();
  return p;
}

std::ostream& operator<<(std::ostream& os, const Percentiles& p) {
  return os << "p50 " << 1e3 * p.p50 << " ms, p95 " << 1e3 * p.p95 << " ms, max " << 1e3 * p.max
            << " ms (" << p.n << " frames)";
}

/// Horizontal distance travelled along the ground truth up to each stamp.
class Odometer {
 public:
  explicit Odometer(const Trajectory& gt) : gt_(gt), d_(gt.size(), 0.0) {
    for (std::size_t i = 1; i < gt.size(); ++i)
      d_[i] = d_[i - 1] + (gt[i].p.head<2>() - gt[i - 1].p.head<2>()).norm();
  }
  double at(double t) const {
    const auto it = std::lower_bound(gt_.begin(), gt_.end(), t,
                                     [](const StampedPose& s, double x) { return s.t < x; });
    if (it == gt_.end()) return d_.empty() ? 0.0 : d_.back();
    return d_[static_cast<std::size_t>(it - gt_.begin())];
  }

 private:
  const Trajectory& gt_;
  std::vector<double> d_;
};

Eigen::Isometry3d nearestPose(const Trajectory& gt, double t) {
  const auto it = std::lower_bound(gt.begin(), gt.end(), t,
                                   [](const StampedPose& s, double x) { return s.t < x; });
  if (it == gt.end()) return gt.back().isometry();
  if (it != gt.begin() && std::abs((it - 1)->t - t) < std::abs(it->t - t))
    return (it - 1)->isometry();
  return it->isometry();
}

void writePose(std::ostream& os, const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  os << " " << T.translation().transpose() << " " << q.x() << " " << q.y() << " " << q.z() << " "
     << q.w();
}

/// --dump PREFIX: PREFIX.graph holds every loop keyframe (N id segment t travelled, odometry,
/// corrected and ground-truth poses) and every loop (L from to active T_from_to, quality), so
/// that the pose graph can be studied without running the system again; PREFIX_{final,odometry,
/// gt}.tum the trajectories.
void dumpGraph(const std::string& prefix, const loop::LoopCloser& lc, const Trajectory& gt,
               const system::SlamSystem& sys) {
  std::ofstream os(prefix + ".graph");
  os << std::setprecision(12);
  for (const loop::LoopKeyframe& k : lc.keyframes()) {
    os << "N " << k.id << " " << k.segment << " " << k.t << " " << k.travelled_m;
    writePose(os, k.T_world_body_odom);
    writePose(os, lc.pose(k.id));
    writePose(os, nearestPose(gt, k.t));
    os << "\n";
  }
  for (const loop::LoopRecord& l : lc.loops()) {
    const loop::LoopConstraint& c = l.constraint;
    os << "L " << c.from_id << " " << c.to_id << " " << (l.rolled_back ? 0 : 1);
    writePose(os, c.T_from_to);
    os << " " << c.pnp_inliers << " " << c.depth_inliers << " " << c.reprojection_rms_px << " "
       << c.depth_rms_m << "\n";
  }
  auto tum = [&](const std::string& name, const Trajectory& tr) {
    std::ofstream f(prefix + "_" + name + ".tum");
    f << std::setprecision(12);
    for (const StampedPose& s : tr)
      f << s.t << " " << s.p.transpose() << " " << s.q.x() << " " << s.q.y() << " " << s.q.z()
        << " " << s.q.w() << "\n";
  };
  tum("final", sys.finalTrajectory());
  tum("odometry", sys.odometryTrajectory());
  tum("online", sys.onlineTrajectory());
  tum("gt", gt);
}

struct RunResult {
  Percentiles all, after_first_loop;
};

/// One threaded run; the source is pumped by `pump` into the sink it is given.
template <typename Pump>
RunResult runOnce(const Args& a, const system::SystemConfig& cfg, bool loop_on,
                  const Trajectory& gt, double lap_m, Pump pump) {
  system::SystemConfig c = cfg;
  c.loop.enable = loop_on;
  system::SlamSystemOptions so;
  so.live = !a.offline;
  const auto cpu0 = std::clock();
  system::SlamSystem sys(c, so);
  std::vector<double> fed, done, loops_at_done;
  fed.reserve(1 << 16);
  done.reserve(1 << 16);
  loops_at_done.reserve(1 << 16);
  PacedSink sink(sys, a.speed, fed);
  std::atomic<bool> stop{false};
  std::thread monitor([&] {
    while (!stop.load()) {
      const system::SlamProgress p = sys.progress();
      while (done.size() < p.frames) {
        done.push_back(secondsSince(sink.start()));
        loops_at_done.push_back(static_cast<double>(p.loops_accepted));
      }
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
  });
  pump(sink);
  stop.store(true);
  monitor.join();
  const double wall = secondsSince(sink.start());
  const double cpu = static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;

  std::vector<double> lat, lat_loop;
  for (std::size_t i = 0; i < std::min(fed.size(), done.size()); ++i) {
    lat.push_back(done[i] - fed[i]);
    if (loops_at_done[i] > 0) lat_loop.push_back(done[i] - fed[i]);
  }
  RunResult r{percentiles(lat), percentiles(lat_loop)};

  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  std::cout << std::fixed << std::setprecision(2) << "\nloop closing " << (loop_on ? "on" : "off")
            << " (" << (a.offline ? "offline" : "live") << " mode, speed " << a.speed
            << "x): " << fed.size() << " frames, wall " << wall << " s, process CPU " << cpu
            << " s\n";
  std::cout << "  odometry latency: " << r.all << "\n";
  if (loop_on) std::cout << "  after the first loop: " << r.after_first_loop << "\n";
  std::cout << std::setprecision(4) << "  ATE posyaw: final "
            << eval::evaluate(gt, sys.finalTrajectory(), eo).ate.rmse << " m, online "
            << eval::evaluate(gt, sys.onlineTrajectory(), eo).ate.rmse << " m, odometry "
            << eval::evaluate(gt, sys.odometryTrajectory(), eo).ate.rmse << " m\n";

  const mapping::Mapper& map = sys.mapper();
  const std::size_t kf = std::max<std::size_t>(1, map.store().size());
  std::cout << std::setprecision(1) << "  keyframes " << map.store().size() << ", map points "
            << map.pointMap().pointCount() << ", keyframe store "
            << static_cast<double>(map.store().memoryBytes()) / static_cast<double>(kf)
            << " B per keyframe";
  if (const loop::LoopCloser* lc = sys.loopCloser()) {
    const loop::LoopStats& st = lc->stats();
    std::cout << "; loop closing (descriptors, place index, graph) "
              << static_cast<double>(lc->memoryBytes()) /
                     static_cast<double>(std::max<std::uint64_t>(1, st.keyframes))
              << " B per loop keyframe (" << st.keyframes << " loop keyframes); loops "
              << st.accepted << ", rolled back " << st.rolled_back << ", solves " << st.solves
              << ", solve max " << st.solve_ms_max << " ms; map corrections "
              << map.stats().corrections << ", max " << map.stats().correction_ms_max << " ms";
  }
  std::cout << "\n";
  if (const loop::LoopCloser* lc = sys.loopCloser()) {
    // Each active loop against the ground truth (nearest pose in time, body frame).
    auto nearest = [&](double t) { return nearestPose(gt, t); };
    double worst_m = 0.0, worst_deg = 0.0;
    for (const loop::LoopRecord& l : lc->loops()) {
      if (l.rolled_back || gt.empty()) continue;
      const auto& kfs = sys.keyframeStates();
      const Eigen::Isometry3d T_true = nearest(kfs.at(l.constraint.from_id).state.t_imu).inverse() *
                                       nearest(kfs.at(l.constraint.to_id).state.t_imu);
      const Eigen::Isometry3d E = T_true.inverse() * l.constraint.T_from_to;
      worst_m = std::max(worst_m, E.translation().norm());
      worst_deg = std::max(worst_deg,
                           std::abs(std::atan2(E.linear()(1, 0), E.linear()(0, 0))) * 180.0 / M_PI);
    }
    std::cout << std::setprecision(3) << "  active loops vs ground truth: worst " << worst_m
              << " m, " << worst_deg << " deg yaw\n";
  }

  if (const loop::LoopCloser* lc = sys.loopCloser(); lc && !a.dump.empty())
    dumpGraph(a.dump, *lc, gt, sys);

  if (lap_m > 0.0) {
    const Odometer odo(gt);
    std::vector<std::size_t> per_lap;
    for (const mapping::KeyframeInsertion& ins : map.insertions()) {
      const auto lap = static_cast<std::size_t>(std::floor(odo.at(ins.t) / lap_m));
      if (per_lap.size() <= lap) per_lap.resize(lap + 1, 0);
      per_lap[lap] += ins.points;
    }
    std::cout << "  points added per lap (" << lap_m << " m):";
    for (std::size_t l = 0; l < per_lap.size(); ++l)
      std::cout << " " << per_lap[l] << (l > 0 && per_lap[0] > 0 ? " (" : "")
                << (l > 0 && per_lap[0] > 0
                        ? std::to_string(static_cast<int>(
                              std::lround(100.0 * static_cast<double>(per_lap[l]) / per_lap[0]))) +
                              " %)"
                        : "");
    std::cout << "\n";
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  std::cout << "  peak RSS of this process so far " << ru.ru_maxrss / 1024 << " MB\n";
  return r;
}

}  // namespace

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
      else if (arg == "--speed")
        a.speed = std::stod(next());
      else if (arg == "--rawlog")
        a.rawlog = next();
      else if (arg == "--gt")
        a.gt = next();
      else if (arg == "--config")
        a.config = next();
      else if (arg == "--loop")
        a.loop = next();
      else if (arg == "--offline")
        a.offline = true;
      else if (arg == "--dump")
        a.dump = next();
      else
        throw std::invalid_argument("unknown argument " + arg);
    }
    if (a.loop != "on" && a.loop != "off" && a.loop != "both")
      throw std::invalid_argument("--loop is on, off or both");
    std::vector<bool> modes;
    if (a.loop != "on") modes.push_back(false);
    if (a.loop != "off") modes.push_back(true);

    IniReader sim_ini = IniReader::empty();
    sim::SimOptions so = sim::SimOptions::load(sim_ini);
    so.profile.kind = sim::parseProfileKind(a.profile);
    so.profile.duration_s = a.duration;
    so.seed = a.seed;
    so.fps = a.fps;
    if (a.rawlog.empty()) {
      const sim::SimulatedSequence seq(so);
      auto ini = IniReader::fromText(sim::slamConfigText(seq), "generated config.ini");
      const system::SystemConfig cfg = system::SystemConfig::load(ini);
      const Trajectory gt = seq.bodyTrajectory();
      std::cout << "simulated " << a.profile << ", " << seq.duration() << " s at " << a.fps
                << " Hz\n";
      for (bool on : modes)
        runOnce(a, cfg, on, gt, seq.profile().lap_length_m,
                [&](MeasurementSink& sink) { seq.pump(sink); });
    } else {
      if (a.gt.empty() || a.config.empty())
        throw std::invalid_argument("--rawlog needs --gt and --config");
      auto ini = IniReader::fromFile(a.config);
      const system::SystemConfig cfg = system::SystemConfig::load(ini);
      const Trajectory gt = eval::readTum(a.gt);
      const double lap = sim::makeMotionProfile(so.profile, cfg.extrinsic.T_body_cam).lap_length_m;
      std::cout << a.rawlog << "\n";
      for (bool on : modes)
        runOnce(a, cfg, on, gt, lap, [&](MeasurementSink& sink) {
          io::RawlogSource source(a.rawlog, cfg.streamConfig());
          source.pump(sink);
        });
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_slam: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
