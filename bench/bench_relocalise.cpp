// Time to first relocalisation in a saved map, on every simulator profile (issue 12). Per
// profile a first run maps the profile's path (variant 0, default duration: at least one lap);
// its map stays in memory (the same MapData rgbdi-slam saves and --load-map reads). Second runs
// start in that map on other paths of the same world (variant 1: another start, driven the
// other way round; variant 2: another start, same direction); two runs in other worlds that must
// never relocalise: another seed's variant 0 (other textures; shorter than a lap, its room is
// sized to the part of the path it covers and its furniture stands only along that part) and
// other furniture ([sim] world_seed, and other textures) along the map's path. Printed per second
// run, as a markdown table:
//   - "joined at": the keyframe that completed the join (a recognised view, or the keyframe at
//     which a confirmed geometric fit was taken), s after the start; "by": views or geometry;
//   - "online from": when the online pose (what a robot has) was first in the map's frame;
//   - ATE in the map's frame: the run's trajectory.tum poses mapped through the FIRST run's
//     alignment to ground truth only (no alignment of their own), and of its online poses;
//   - the worst error of the joining loop edges against ground truth (map keyframe at its
//     first-run time, query keyframe at its time in the second run): a wrong join shows here;
//   - wall time of the second run (threaded, offline mode, as fast as it goes).
//
//   bench_relocalise [--profiles a,b,...] [--fps N] [--duration S] [--variants 1,2]
//                    [--seed N] [--other-seed N] [--other-world-seed N (0: no such row)]
//                    [--detail]
// --detail also lists, per second run, every loop edge to the map (position and yaw error against
// ground truth) and the map-frame position error of the final and online poses once a second.
// --duration is the second runs' length (default 10 s); the first run uses the profile's own.
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_system.h"

using namespace rgbdi;
using Clock = std::chrono::steady_clock;

namespace {

struct Args {
  std::vector<std::string> profiles = {"handheld", "wheeled_circle", "wheeled_slopes",
                                       "tracked_slopes"};
  std::vector<int> variants = {1, 2};
  double fps = 15.0, duration = 10.0;
  std::uint64_t seed = 1, other_seed = 7;
  /// [sim] world_seed of the other-furniture world (0: no such row).
  std::uint64_t other_world_seed = 7;
  bool detail = false;
};

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

sim::SimOptions simOptions(const std::string& profile, int variant, double duration_s, double fps,
                           std::uint64_t seed) {
  auto ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::parseProfileKind(profile);
  so.profile.variant = variant;
  so.profile.duration_s = duration_s;
  so.fps = fps;
  so.seed = seed;
  return so;
}

struct Session {
  std::unique_ptr<sim::SimulatedSequence> seq;
  std::unique_ptr<system::SlamSystem> sys;
  double wall_s = 0.0;
};

Session runSession(const sim::SimOptions& so, std::shared_ptr<const map::MapData> map) {
  Session s;
  s.seq = std::make_unique<sim::SimulatedSequence>(so);
  auto ini = IniReader::fromText(sim::slamConfigText(*s.seq), "generated config.ini");
  const system::SystemConfig cfg = system::SystemConfig::load(ini);
  system::SlamSystemOptions opt;
  opt.map = std::move(map);
  s.sys = std::make_unique<system::SlamSystem>(cfg, opt);
  const auto t0 = Clock::now();
  s.seq->pump(*s.sys);
  s.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return s;
}

double ateThrough(const Trajectory& gt, const Trajectory& est, const Eigen::Isometry3d& T_gt_map) {
  if (est.empty()) return -1.0;
  Trajectory moved;
  moved.reserve(est.size());
  for (const StampedPose& p : est)
    moved.push_back(StampedPose::fromIsometry(p.t, T_gt_map * p.isometry()));
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::None;
  return eval::evaluate(gt, moved, eo).ate.rmse;
}

std::string seconds(double t) {
  if (t < 0.0) return "never";
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << t;
  return os.str();
}

std::string cm(double m) {
  if (m < 0.0) return "-";
  std::ostringstream os;
  os << std::fixed << std::setprecision(2) << 100.0 * m;
  return os.str();
}

/// Position error [m] of `est`'s pose nearest to `t` mapped through T_gt_map, or -1.
double errorAt(const Trajectory& est, const sim::SimulatedSequence& seq, double t,
               const Eigen::Isometry3d& T_gt_map) {
  const StampedPose* best = nullptr;
  for (const StampedPose& p : est)
    if (!best || std::abs(p.t - t) < std::abs(best->t - t)) best = &p;
  if (!best || std::abs(best->t - t) > 0.1) return -1.0;
  return ((T_gt_map * best->isometry()).translation() -
          seq.groundTruth(best->t).T_world_body.translation())
      .norm();
}

void printDetail(const sim::SimulatedSequence& seq, const Session& first,
                 const system::SlamSystem& sys,
                 const std::unordered_map<std::uint64_t, double>& map_t,
                 const Eigen::Isometry3d& T_gt_map) {
  const double t0 = seq.frameStamp(0);
  if (const auto* lc = sys.loopCloser())
    for (const loop::LoopRecord& lr : lc->loops()) {
      const auto it = map_t.find(lr.constraint.from_id);
      if (it == map_t.end()) continue;
      const Eigen::Isometry3d E = (first.seq->groundTruth(it->second).T_world_body.inverse() *
                                   seq.groundTruth(lr.t_query).T_world_body)
                                      .inverse() *
                                  lr.constraint.T_from_to;
      std::cout << "    map loop at " << std::fixed << std::setprecision(2) << lr.t_query - t0
                << " s: map keyframe " << lr.constraint.from_id << " (first run "
                << it->second - first.seq->frameStamp(0) << " s), error "
                << cm(E.translation().norm()) << " cm, yaw " << std::setprecision(3)
                << std::atan2(E.linear()(1, 0), E.linear()(0, 0)) * 180.0 / M_PI << " deg"
                << (lr.rolled_back ? " (rolled back)" : "") << "\n";
    }
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  const eval::EvalResult odo = eval::evaluate(seq.bodyTrajectory(), sys.odometryTrajectory(), eo);
  std::cout << "    odometry alone (own position+yaw alignment): ATE " << cm(odo.ate.rmse)
            << " cm, max " << cm(odo.ate.max) << " cm\n";
  for (double t = 1.0; t < seq.duration(); t += 1.0)
    std::cout << "    t " << std::setprecision(0) << t << " s: error final "
              << cm(errorAt(sys.finalTrajectory(), seq, t0 + t, T_gt_map)) << " cm, online "
              << cm(errorAt(sys.onlineTrajectory(), seq, t0 + t, T_gt_map)) << " cm\n";
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    const bool has = i + 1 < argc;
    if (k == "--profiles" && has) {
      a.profiles = splitList(argv[++i]);
    } else if (k == "--variants" && has) {
      a.variants.clear();
      for (const std::string& v : splitList(argv[++i])) a.variants.push_back(std::stoi(v));
    } else if (k == "--fps" && has) {
      a.fps = std::stod(argv[++i]);
    } else if (k == "--duration" && has) {
      a.duration = std::stod(argv[++i]);
    } else if (k == "--seed" && has) {
      a.seed = std::stoull(argv[++i]);
    } else if (k == "--other-seed" && has) {
      a.other_seed = std::stoull(argv[++i]);
    } else if (k == "--other-world-seed" && has) {
      a.other_world_seed = std::stoull(argv[++i]);
    } else if (k == "--detail") {
      a.detail = true;
    } else {
      std::cerr << "usage: bench_relocalise [--profiles a,b,...] [--fps N] [--duration S] "
                   "[--variants 1,2] [--seed N] [--other-seed N] [--other-world-seed N] "
                   "[--detail]\n";
      return 2;
    }
  }

  std::cout << "| profile | second run | joined at [s] | by | online from [s] | joins | ATE map "
               "frame [cm] | ATE online [cm] | worst join edge [cm] | geometric searches (fits / "
               "ambiguous / disagreeing fits / confirmed / joins refused) | ms per search (mean / "
               "max) | wall [s] |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& profile : a.profiles) {
    const Session first = runSession(simOptions(profile, 0, 0.0, a.fps, a.seed), nullptr);
    eval::EvalOptions eo;
    eo.align = eval::AlignMode::PosYaw;
    const eval::EvalResult ev =
        eval::evaluate(first.seq->bodyTrajectory(), first.sys->finalTrajectory(), eo);
    const Eigen::Isometry3d T_gt_map = ev.alignment.rigid();
    const auto map = std::make_shared<const map::MapData>(first.sys->mapToSave());
    std::cout << "| " << profile << " | first run (map): " << seconds(first.seq->duration())
              << " s, " << map->places.size() << " place keyframes | | | | | " << cm(ev.ate.rmse)
              << " | | | | | " << seconds(first.wall_s) << " |\n";
    std::unordered_map<std::uint64_t, double> map_t;  // map keyframe id -> first-run stamp
    for (const loop::LoopKeyframe& k : map->places) map_t[k.id] = k.t;

    struct Second {
      std::string label;
      sim::SimOptions so;
    };
    std::vector<Second> seconds_runs;
    for (int v : a.variants)
      seconds_runs.push_back(
          {"variant " + std::to_string(v), simOptions(profile, v, a.duration, a.fps, a.seed)});
    // Variant 0 shorter than a lap is a world of its own: the room is sized to the part of the
    // path it covers, furniture only along that part (profiles.h).
    seconds_runs.push_back({"seed " + std::to_string(a.other_seed) + ", variant 0 (own room)",
                            simOptions(profile, 0, a.duration, a.fps, a.other_seed)});
    if (a.other_world_seed != 0) {
      // Other furniture (and textures): the geometry differs too.
      Second w{"other furniture (world_seed " + std::to_string(a.other_world_seed) + ")",
               simOptions(profile, 0, a.duration, a.fps, a.other_seed)};
      w.so.scene.world_seed = a.other_world_seed;
      seconds_runs.push_back(w);
    }
    for (const Second& r : seconds_runs) {
      const Session s = runSession(r.so, map);
      const double t0 = s.seq->frameStamp(0);
      const double t_view = s.sys->firstRelocalisationTime();
      const double t_online = s.sys->firstOnlinePoseInMapTime();
      const auto* lc = s.sys->loopCloser();
      const Trajectory gt = s.seq->bodyTrajectory();
      double worst_edge = -1.0;
      if (lc)
        for (const loop::LoopRecord& lr : lc->loops()) {
          const auto it = map_t.find(lr.constraint.from_id);
          if (it == map_t.end()) continue;  // a loop within the run
          const Eigen::Isometry3d T_gt = first.seq->groundTruth(it->second).T_world_body.inverse() *
                                         s.seq->groundTruth(lr.t_query).T_world_body;
          const double e = (T_gt.inverse() * lr.constraint.T_from_to).translation().norm();
          worst_edge = std::max(worst_edge, e);
        }
      if (a.detail) printDetail(*s.seq, first, *s.sys, map_t, T_gt_map);
      std::string by = "-";
      if (lc)
        for (const loop::JoinRecord& j : lc->joins())
          if (j.to_segment == 0) {
            by = j.geometric ? "geometry" : "views";
            break;
          }
      std::string geo = "-", geo_ms = "-";
      if (const system::GeoRelocStage* g = lc ? s.sys->geoReloc() : nullptr) {
        const system::GeoRelocReport rep = g->report();
        const loop::LoopStats& st = lc->stats();
        geo = std::to_string(rep.results) + " (" + std::to_string(rep.fits) + " / " +
              std::to_string(rep.ambiguous) + " / " + std::to_string(rep.disagreements) + " / " +
              std::to_string(rep.confirmed) + " / " +
              std::to_string(st.geometric_refused_free_space + st.geometric_refused_no_neighbour) +
              ")";
        std::ostringstream ms;
        ms << std::fixed << std::setprecision(0)
           << (rep.searched > 0 ? rep.ms_total / static_cast<double>(rep.searched) : 0.0) << " / "
           << rep.ms_max;
        geo_ms = ms.str();
      }
      std::cout << "| " << profile << " | " << r.label << " | "
                << seconds(t_view < 0 ? -1.0 : t_view - t0) << " | " << by << " | "
                << seconds(t_online < 0 ? -1.0 : t_online - t0) << " | "
                << (lc ? lc->joins().size() : 0) << " | "
                << cm(ateThrough(gt, s.sys->finalTrajectory(), T_gt_map)) << " | "
                << cm(ateThrough(gt, s.sys->onlineTrajectory(), T_gt_map)) << " | "
                << cm(worst_edge) << " | " << geo << " | " << geo_ms << " | " << seconds(s.wall_s)
                << " |" << std::endl;
    }
  }
  return 0;
}
