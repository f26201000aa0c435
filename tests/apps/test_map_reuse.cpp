// Map reuse end to end on generated sequences (issue 12): a second run that loads the map of a
// first run in the same world relocalises early and is then in the map's frame (its ATE taken
// through the first run's alignment to ground truth only); localize-only leaves the map as it
// was; a run in another world never relocalises; a run driven the other way round (views the
// map never saw) relocalises by geometry; a run in the same room with other furniture is never
// joined elsewhere. Runs the same SlamSystem rgbdi-slam runs.
#include <gtest/gtest.h>

#include <iomanip>
#include <iostream>
#include <memory>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_system.h"

using namespace rgbdi;

namespace {

/// The wheeled robot's circle at 0.8 m/s (a 16 s lap); variant 2 starts elsewhere on it.
sim::SimOptions circle(double duration_s, int variant = 0, std::uint64_t seed = 1) {
  auto ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::ProfileKind::WheeledCircle;
  so.profile.speed_m_s = 0.8;
  so.profile.duration_s = duration_s;
  so.fps = 15.0;
  so.seed = seed;
  so.profile.variant = variant;
  return so;
}

struct SessionRun {
  std::unique_ptr<sim::SimulatedSequence> seq;
  std::unique_ptr<system::SlamSystem> sys;
};

SessionRun run(const sim::SimOptions& so, std::shared_ptr<const map::MapData> map = nullptr,
               bool localize_only = false, bool threaded = true, double track_interval_m = 0.0) {
  SessionRun r;
  r.seq = std::make_unique<sim::SimulatedSequence>(so);
  auto ini = IniReader::fromText(sim::slamConfigText(*r.seq), "generated config.ini");
  system::SystemConfig cfg = system::SystemConfig::load(ini);
  cfg.reloc.track_interval_m = track_interval_m;  // tracking after the join (off by default)
  system::SlamSystemOptions opt;
  opt.map = std::move(map);
  opt.localize_only = localize_only;
  opt.threaded = threaded;
  r.sys = std::make_unique<system::SlamSystem>(cfg, opt);
  r.seq->pump(*r.sys);
  return r;
}

/// ATE of `est` mapped by T_gt_map, without any alignment of its own.
double ateInMapFrame(const Trajectory& gt, const Trajectory& est,
                     const Eigen::Isometry3d& T_gt_map) {
  Trajectory moved;
  for (const StampedPose& p : est)
    moved.push_back(StampedPose::fromIsometry(p.t, T_gt_map * p.isometry()));
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::None;
  return eval::evaluate(gt, moved, eo).ate.rmse;
}

/// A mapping run's saved map and its alignment to ground truth.
struct FirstRun {
  std::shared_ptr<const map::MapData> map;
  Eigen::Isometry3d T_gt_map = Eigen::Isometry3d::Identity();
  double ate = 0.0;
};

FirstRun mapRun(const sim::SimOptions& so) {
  FirstRun out;
  SessionRun a = run(so);
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  const eval::EvalResult ev = eval::evaluate(a.seq->bodyTrajectory(), a.sys->finalTrajectory(), eo);
  out.T_gt_map = ev.alignment.rigid();
  out.ate = ev.ate.rmse;
  out.map = std::make_shared<const map::MapData>(a.sys->mapToSave());
  return out;
}

/// The first run's map, shared by the tests of this file.
const FirstRun& firstRun() {
  static const FirstRun f = [] {
    FirstRun out = mapRun(circle(20.0));
    std::cout << "first run: ATE " << out.ate << " m, " << out.map->places.size()
              << " place keyframes, " << out.map->keyframes.size() << " keyframes" << std::endl;
    return out;
  }();
  return f;
}

}  // namespace

TEST(MapReuse, ASecondRunRelocalisesEarlyAndIsInTheMapsFrame) {
  const FirstRun& first = firstRun();
  ASSERT_GT(first.map->places.size(), 20u);
  SessionRun b = run(circle(10.0, 2), first.map);
  const system::SlamSystem& sys = *b.sys;
  EXPECT_EQ(sys.mapState(), system::MapState::kLocalised);
  const double t_reloc = sys.firstRelocalisationTime();
  ASSERT_GE(t_reloc, 0.0) << "never relocalised";
  const double since_start = t_reloc - b.seq->frameStamp(0);
  const loop::LoopStats& ls = sys.loopCloser()->stats();
  std::cout << "relocalised " << since_start << " s after the start; joining matches with too "
            << "few inliers " << ls.join_matches_weak << ", unconfirmed " << ls.join_matches_dropped
            << std::endl;
  // Issue 12: within 3 s of the start. The run starts with 2 s at rest: the view at rest is
  // recognised (joining candidates need no reference score, and a part not yet placed sends
  // its keyframes from the window).
  EXPECT_LE(since_start, 3.0);
  // What a robot has: its online pose is in the map's frame within 3 s too.
  const double online_from = sys.firstOnlinePoseInMapTime() - b.seq->frameStamp(0);
  std::cout << "online poses in the map's frame from " << online_from << " s" << std::endl;
  EXPECT_GE(online_from, since_start);
  EXPECT_LE(online_from, 3.0);
  // Keyframe ids continue the map's.
  EXPECT_EQ(sys.firstKeyframeId(), first.map->manifest.next_keyframe_id);
  // Every pose of trajectory.tum is in the map's frame: ATE through the first run's alignment.
  const Trajectory traj = sys.finalTrajectory();
  ASSERT_GT(traj.size(), 100u);
  const double ate = ateInMapFrame(b.seq->bodyTrajectory(), traj, first.T_gt_map);
  std::cout << "second run: ATE in the map frame " << ate << " m" << std::endl;
  EXPECT_LE(ate, 0.03);
  // The online trajectory starts at the relocalisation.
  const Trajectory online = sys.onlineTrajectory();
  ASSERT_FALSE(online.empty());
  EXPECT_GE(online.front().t, t_reloc - 1e-9);
  EXPECT_LE(ateInMapFrame(b.seq->bodyTrajectory(), online, first.T_gt_map), 0.05);
  // Mapping mode: the saved map holds both runs, the first run's keyframes unchanged.
  const map::MapData both = sys.mapToSave();
  EXPECT_GT(both.places.size(), first.map->places.size());
  EXPECT_EQ(both.manifest.sessions, 2);
  for (std::size_t i = 0; i < first.map->places.size(); ++i) {
    ASSERT_EQ(both.places[i].id, first.map->places[i].id);
    EXPECT_TRUE(both.places[i].T_world_body.isApprox(first.map->places[i].T_world_body, 1e-12));
  }
}

TEST(MapReuse, LocalizeOnlyLeavesTheMapAsItWas) {
  const FirstRun& first = firstRun();
  SessionRun c = run(circle(10.0, 2), first.map, /*localize_only=*/true);
  EXPECT_EQ(c.sys->mapState(), system::MapState::kLocalised);
  EXPECT_EQ(c.sys->mapper().store().size(), first.map->keyframes.size());
  const double ate =
      ateInMapFrame(c.seq->bodyTrajectory(), c.sys->finalTrajectory(), first.T_gt_map);
  EXPECT_LE(ate, 0.03);
}

TEST(MapReuse, ARunInAnotherWorldNeverRelocalises) {
  const FirstRun& first = firstRun();
  // Other furniture (and other textures) along the same path in a room of the same size: the
  // walls fit, the furniture does not, by views nor by geometry.
  sim::SimOptions other = circle(10.0, 0, /*seed=*/7);
  other.scene.world_seed = 7;
  SessionRun d = run(other, first.map);
  EXPECT_EQ(d.sys->mapState(), system::MapState::kNotLocalised);
  EXPECT_LT(d.sys->firstRelocalisationTime(), 0.0);
  EXPECT_TRUE(d.sys->finalTrajectory().empty());
  EXPECT_TRUE(d.sys->onlineTrajectory().empty());
  EXPECT_FALSE(d.sys->odometryTrajectory().empty());
  ASSERT_NE(d.sys->loopCloser(), nullptr);
  EXPECT_EQ(d.sys->loopCloser()->stats().joins, 0u);
}

// Issue 36: driven the other way round (variant 1) the camera sees the furniture from sides the
// map never saw: no view is recognised, but the shape of the place is: geometric relocalisation
// places the run, and a threaded run gives exactly the sequential run's poses.
TEST(MapReuse, ARunDrivenTheOtherWayRelocalisesByGeometry) {
  const FirstRun& first = firstRun();
  // With tracking after the join (its edges must be the same threaded and sequential).
  SessionRun b = run(circle(12.0, 1), first.map, /*localize_only=*/false, /*threaded=*/true, 0.25);
  const system::SlamSystem& sys = *b.sys;
  ASSERT_EQ(sys.mapState(), system::MapState::kLocalised);
  const loop::LoopCloser* lc = sys.loopCloser();
  ASSERT_NE(lc, nullptr);
  ASSERT_FALSE(lc->joins().empty());
  EXPECT_TRUE(lc->joins().front().geometric);
  EXPECT_EQ(lc->joins().front().to_segment, 0);
  const double since_start = sys.firstRelocalisationTime() - b.seq->frameStamp(0);
  const system::GeoRelocReport rep = sys.geoReloc()->report();
  std::cout << "joined by geometry " << since_start << " s after the start; searches "
            << rep.results << " (fits " << rep.fits << ", ambiguous " << rep.ambiguous << "), mean "
            << rep.ms_total / static_cast<double>(rep.searched) << " ms" << std::endl;
  EXPECT_LE(since_start, 10.0);
  EXPECT_GE(rep.confirmed, 1u);
  const double ate = ateInMapFrame(b.seq->bodyTrajectory(), sys.finalTrajectory(), first.T_gt_map);
  std::cout << "map-frame ATE " << ate << " m" << std::endl;
  EXPECT_LE(ate, 0.03);

  SessionRun c = run(circle(12.0, 1), first.map, /*localize_only=*/false, /*threaded=*/false, 0.25);
  const Trajectory a_traj = sys.finalTrajectory(), c_traj = c.sys->finalTrajectory();
  ASSERT_EQ(a_traj.size(), c_traj.size());
  for (std::size_t i = 0; i < a_traj.size(); ++i) {
    ASSERT_EQ(a_traj[i].t, c_traj[i].t);
    ASSERT_EQ(a_traj[i].isometry().matrix(), c_traj[i].isometry().matrix()) << i;
  }
  EXPECT_EQ(c.sys->geoReloc()->report().results, rep.results);
  // Tracking after the join: fits were taken and some added edges (the loop closer may still
  // refuse a fit: free space, no map keyframe near), the same in both runs.
  const std::uint64_t edges_by = lc->stats().tracking_fits;
  std::cout << "tracking fits " << rep.track_fits << " of " << rep.track_results << ", " << edges_by
            << " added edges" << std::endl;
  EXPECT_GE(edges_by, 1u);
  EXPECT_LE(edges_by, rep.track_fits);
  EXPECT_EQ(c.sys->geoReloc()->report().track_fits, rep.track_fits);
  EXPECT_EQ(c.sys->loopCloser()->stats().tracking_fits, edges_by);
}

// In localize-only mode a geometric relocalisation holds to the end of the run: every online
// pose after it is in the map's frame.
TEST(MapReuse, LocalizeOnlyStaysInTheMapAfterAGeometricRelocalisation) {
  const FirstRun& first = firstRun();
  SessionRun b = run(circle(16.0, 1), first.map, /*localize_only=*/true);
  const system::SlamSystem& sys = *b.sys;
  ASSERT_EQ(sys.mapState(), system::MapState::kLocalised);
  ASSERT_TRUE(sys.loopCloser()->joins().front().geometric);
  EXPECT_EQ(sys.mapper().store().size(), first.map->keyframes.size());
  const double t_online = sys.firstOnlinePoseInMapTime();
  ASSERT_GE(t_online, 0.0);
  std::size_t after = 0;
  for (const system::FrameRecord& r : sys.frames())
    if (r.t_imu >= t_online) {
      EXPECT_TRUE(r.online_in_map) << r.t_imu;
      ++after;
    }
  EXPECT_GT(after, 30u);
  EXPECT_LE(ateInMapFrame(b.seq->bodyTrajectory(), sys.onlineTrajectory(), first.T_gt_map), 0.05);
  EXPECT_LE(ateInMapFrame(b.seq->bodyTrajectory(), sys.finalTrajectory(), first.T_gt_map), 0.03);
}

// Issue 36: two identical rooms ([sim] twin_rooms): a map of one lap holds both twins, and a run
// driven the other way round in them must not be placed by geometry in the wrong twin. The
// search sees both (ambiguous) and waits; a join, if any, is by views and correct.
TEST(MapReuse, TwinRoomsAreAmbiguousNotGuessed) {
  sim::SimOptions map_so = circle(20.0);
  map_so.scene.twin_rooms = true;
  const FirstRun mapped = mapRun(map_so);
  sim::SimOptions so = circle(12.0, 1);
  so.scene.twin_rooms = true;
  SessionRun b = run(so, mapped.map);
  const system::GeoRelocReport rep = b.sys->geoReloc()->report();
  std::cout << "twin rooms: searches " << rep.results << ", ambiguous " << rep.ambiguous
            << " (most places " << rep.max_places << "), fits " << rep.fits << ", confirmed "
            << rep.confirmed << std::endl;
  EXPECT_GT(rep.ambiguous, 0u);
  EXPECT_GE(rep.max_places, 2);
  for (const loop::JoinRecord& j : b.sys->loopCloser()->joins()) EXPECT_FALSE(j.geometric);
  if (b.sys->mapState() == system::MapState::kLocalised) {
    EXPECT_LE(ateInMapFrame(b.seq->bodyTrajectory(), b.sys->finalTrajectory(), mapped.T_gt_map),
              0.03);
  }
}

// The same room with other furniture (a furniture-moved building): a map of part of a hand-held
// lap furnishes only that part (doc/simulator.md "Variants"); variant 1 drives the whole lap's
// world the other way round. Its walls and their textures are the map's, its furniture is not.
// Joined by views with 4.98 % of the neighbourhood's free-space samples in conflict, it once
// put every pose 4.1 m off (relocalize_check_max_conflict_fraction was 0.05). The short run's
// room is fitted to its part of the path, 0.75 m off the lap's (truth_navmap.yaml origins), so
// a join right against the walls is up to ~0.8 m off the ground truth: a join may be refused or
// made, but never metres off.
TEST(MapReuse, TheSameRoomWithOtherFurnitureIsNotJoinedElsewhere) {
  auto empty = IniReader::empty();
  sim::SimOptions map_so = sim::SimOptions::load(empty);
  map_so.profile.kind = sim::ProfileKind::Handheld;
  map_so.profile.duration_s = 20.0;
  const FirstRun mapped = mapRun(map_so);
  sim::SimOptions so = map_so;
  so.profile.duration_s = 10.0;
  so.profile.variant = 1;
  SessionRun b = run(so, mapped.map, /*localize_only=*/true);
  const auto& joins = b.sys->loopCloser()->joins();
  std::cout << "same room, other furniture: " << joins.size() << " joins, refused by free space "
            << b.sys->loopCloser()->stats().joins_refused_free_space << std::endl;
  if (b.sys->mapState() == system::MapState::kLocalised) {
    EXPECT_LE(ateInMapFrame(b.seq->bodyTrajectory(), b.sys->finalTrajectory(), mapped.T_gt_map),
              1.0);
  }
}
