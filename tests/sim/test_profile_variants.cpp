// Profile variants (issue 12 point 6): further sequences of the same world. Every variant runs
// along the corridor of the world's path (the furniture keeps clear of it), on its ground
// (same heights on the ramps, nose up when climbing), in its stated direction, from another
// start; the scene is the world's whatever the variant and the run's duration; the option is
// read from [sim], validated and written to simulation.ini.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"

namespace rgbdi::sim {
namespace {

const Eigen::Isometry3d& bodyCam() {
  static const Eigen::Isometry3d T = [] {
    Eigen::Isometry3d t = ExtrinsicOptions().T_body_cam;
    t.linear() = Eigen::Quaterniond(t.rotation()).normalized().toRotationMatrix();
    return t;
  }();
  return T;
}

MotionProfile profileOf(ProfileKind kind, int variant, double duration_s = 0.0) {
  ProfileOptions o;
  o.kind = kind;
  o.variant = variant;
  o.duration_s = duration_s;
  return makeMotionProfile(o, bodyCam());
}

double distanceToPolyline(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& line) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < line.size(); ++i) {
    const Eigen::Vector2d a = line[i - 1], ab = line[i] - a;
    const double t = std::clamp((p - a).dot(ab) / std::max(1e-12, ab.squaredNorm()), 0.0, 1.0);
    best = std::min(best, (p - (a + t * ab)).norm());
  }
  return best;
}

struct Sample {
  double t;
  Eigen::Vector3d p, v, forward;  // body position, velocity, body x axis (all world)
};

std::vector<Sample> sampleRun(const MotionProfile& prof, double dt) {
  std::vector<Sample> s;
  for (double t = 0.0; t <= prof.trajectory->duration(); t += dt) {
    const Eigen::Isometry3d T = prof.trajectory->pose(t);
    const Eigen::Isometry3d T2 = prof.trajectory->pose(t + 1e-3);
    s.push_back(
        {t, T.translation(), (T2.translation() - T.translation()) / 1e-3, T.linear().col(0)});
  }
  return s;
}

/// Index of the sample of `run` nearest to p in the ground plane.
std::size_t nearest(const std::vector<Sample>& run, const Eigen::Vector3d& p) {
  std::size_t best = 0;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < run.size(); ++i) {
    const double e = (run[i].p - p).head<2>().norm();
    if (e < d) d = e, best = i;
  }
  return best;
}

}  // namespace

TEST(ProfileVariants, EveryVariantDrivesAlongTheCorridorOfTheWorldsPath) {
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const MotionProfile world = profileOf(kind, 0);
    const bool handheld = kind == ProfileKind::Handheld;
    // The default duration (a lap or more) and a run shorter than a lap (a second session's
    // 10 s): a short variant must still run on the world's path, not beside it.
    for (const double duration_s : {0.0, 10.0})
      for (int variant = duration_s > 0.0 ? 1 : 0; variant < kProfileVariants; ++variant) {
        SCOPED_TRACE(name + " variant " + std::to_string(variant) + ", duration " +
                     std::to_string(duration_s) + " s");
        const MotionProfile prof = profileOf(kind, variant, duration_s);
        // The world (room, ramps, furniture corridor) is the same for every variant.
        EXPECT_EQ(prof.layout.path_xy, world.layout.path_xy);
        EXPECT_EQ(prof.layout.room_min, world.layout.room_min);
        EXPECT_EQ(prof.layout.room_max, world.layout.room_max);
        EXPECT_EQ(prof.layout.ramps.size(), world.layout.ramps.size());
        EXPECT_DOUBLE_EQ(prof.lap_length_m, world.lap_length_m);
        // Same speed profile: same distance in the same time.
        if (duration_s == 0.0) EXPECT_NEAR(prof.path_length_m, world.path_length_m, 1e-9);
        double worst = 0.0;
        for (const Sample& s : sampleRun(prof, 0.1)) {
          // The walker sways by up to ~0.15 m; the robots stay on the path's line.
          worst = std::max(worst, distanceToPolyline(s.p.head<2>(), world.layout.path_xy));
          ASSERT_GT(s.p.x(), world.layout.room_min.x() + world.layout.path_clearance_m);
          ASSERT_LT(s.p.x(), world.layout.room_max.x() - world.layout.path_clearance_m);
        }
        EXPECT_LT(worst, handheld ? 0.2 : 0.01);
      }
  }
}

TEST(ProfileVariants, VariantsRideOnTheWorldsGroundFacingTheirDirectionOfTravel) {
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const bool handheld = kind == ProfileKind::Handheld;
    const std::vector<Sample> world = sampleRun(profileOf(kind, 0), 0.02);
    for (int variant = 1; variant < kProfileVariants; ++variant) {
      SCOPED_TRACE(name + " variant " + std::to_string(variant));
      const MotionProfile prof = profileOf(kind, variant);
      int climbing = 0, same_way = 0, other_way = 0;
      double worst_dz = 0.0;
      const std::vector<Sample> run = sampleRun(prof, 0.1);
      for (std::size_t i = 5; i + 5 < run.size(); ++i) {
        const Sample& s = run[i];
        if (s.v.head<2>().norm() < 0.1) continue;  // at rest: no direction of travel
        // The body looks where it drives (a reversed run is turned round, not driving backwards).
        // Direction over +-0.5 s: where the pitch changes fast (the tracked robot's step) the
        // body origin, above the ground along the tilting chassis, swings back for an instant.
        const Eigen::Vector2d dir = (run[i + 5].p - run[i - 5].p).head<2>().normalized();
        ASSERT_GT(dir.dot(s.forward.head<2>().normalized()), handheld ? 0.6 : 0.95) << s.t;
        const Sample& w = world[nearest(world, s.p)];
        if (w.v.head<2>().norm() > 0.1)
          (dir.dot(w.v.head<2>().normalized()) > 0.0 ? same_way : other_way)++;
        if (handheld) continue;  // the walker bobs up and down by ~0.1 m
        // Slopes over +-0.5 s (the vibration's vertical velocity would swamp an instantaneous
        // one); "steady" where both half windows agree (not on the edge of a ramp or the step,
        // where the body origin swings with the tilting chassis).
        const auto slopeBetween = [&](std::size_t a, std::size_t b) {
          const Eigen::Vector3d d = run[b].p - run[a].p;
          return d.z() / d.head<2>().norm();
        };
        const double slope = slopeBetween(i - 5, i + 5);
        const bool steady = std::abs(slopeBetween(i - 5, i) - slopeBetween(i, i + 5)) < 0.01;
        if (!steady) continue;
        // Same ground: the same height where the world's run passes (ramps and platform).
        worst_dz = std::max(worst_dz, std::abs(s.p.z() - w.p.z()));
        // Uphill lifts the nose: the slope of the motion and the body's pitch agree.
        if (std::abs(slope) > 0.05) {
          EXPECT_GT(slope * s.forward.z(), 0.0) << "slope " << slope << " at t = " << s.t;
          EXPECT_NEAR(s.forward.z() / s.forward.head<2>().norm(), slope, 0.05) << s.t;
          ++climbing;
        }
      }
      if (variant == 1) {
        EXPECT_GT(other_way, 50) << same_way;
        EXPECT_LT(same_way, other_way / 20 + 1) << other_way;
      } else {
        EXPECT_GT(same_way, 50) << other_way;
        EXPECT_LT(other_way, same_way / 20 + 1) << same_way;
      }
      if (!handheld) {
        EXPECT_LT(worst_dz, 0.02);
        if (kind != ProfileKind::WheeledCircle) {
          EXPECT_GT(climbing, 5) << "no ramp on the run";
        }
      }
    }
  }
}

TEST(ProfileVariants, EveryVariantStartsAtRestSomewhereElse) {
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const Eigen::Isometry3d start0 = profileOf(kind, 0).trajectory->pose(0.0);
    std::vector<Eigen::Isometry3d> starts{start0};
    for (int variant = 1; variant < kProfileVariants; ++variant) {
      SCOPED_TRACE(name + " variant " + std::to_string(variant));
      const MotionProfile prof = profileOf(kind, variant);
      const Eigen::Isometry3d s = prof.trajectory->pose(0.0);
      // At rest until moving_start_s, level on flat ground.
      EXPECT_LT(
          (prof.trajectory->pose(0.5 * prof.moving_start_s).translation() - s.translation()).norm(),
          1e-9);
      EXPECT_NEAR(s.translation().z(), start0.translation().z(), 1e-9);
      for (const Eigen::Isometry3d& other : starts)
        EXPECT_GT((s.translation() - other.translation()).norm(), 1.0);
      starts.push_back(s);
    }
  }
}

// How soon a variant's camera sees a place as variant 0's camera saw it (within 1 m and 45 deg
// of viewing direction): what relocalisation in a map of variant 0 can hope for. Variant 2
// drives the same way along the same path: at once. Variant 1 looks the other way round; its
// figure is printed (an upper bound of what a relocaliser can do on it).
TEST(ProfileVariants, Variant2SeesAVariant0ViewFromItsStart) {
  const double cos45 = std::cos(45.0 * M_PI / 180.0);
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const MotionProfile world = profileOf(kind, 0);
    std::vector<Eigen::Isometry3d> views;
    for (double t = 0.0; t <= world.trajectory->duration(); t += 0.1)
      views.push_back(world.trajectory->pose(t) * bodyCam());
    for (int variant = 1; variant < kProfileVariants; ++variant) {
      const MotionProfile prof = profileOf(kind, variant);
      double first = -1.0, closest = std::numeric_limits<double>::infinity();
      for (double t = 0.0; t <= prof.trajectory->duration() && first < 0.0; t += 0.1) {
        const Eigen::Isometry3d c = prof.trajectory->pose(t) * bodyCam();
        for (const Eigen::Isometry3d& v : views) {
          if (v.linear().col(2).dot(c.linear().col(2)) < cos45) continue;
          const double d = (v.translation() - c.translation()).norm();
          closest = std::min(closest, d);
          if (d < 1.0) {
            first = t;
            break;
          }
        }
      }
      std::printf("%-15s variant %d: first view within 1 m / 45 deg of a variant-0 view at %s\n",
                  name.c_str(), variant,
                  first < 0.0 ? ("never (closest " + std::to_string(closest) + " m)").c_str()
                              : (std::to_string(first) + " s").c_str());
      if (variant == 2) {
        EXPECT_EQ(first, 0.0) << name;
      }
    }
  }
}

TEST(ProfileVariants, TheSceneIsTheWorldsForEveryVariantAndDuration) {
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const MotionProfile world = profileOf(kind, 0);
    const Scene reference = buildProfileScene(world, 7);
    ASSERT_GT(reference.primitiveCount(), 20u);
    const double longer = 1.5 * world.trajectory->duration();
    for (const auto& [variant, duration] : std::vector<std::pair<int, double>>{
             {1, 0.0}, {2, 0.0}, {1, 20.0}, {2, longer}, {0, longer}}) {
      SCOPED_TRACE(name + " variant " + std::to_string(variant) + " duration " +
                   std::to_string(duration));
      const Scene scene = buildProfileScene(profileOf(kind, variant, duration), 7);
      ASSERT_EQ(scene.primitiveCount(), reference.primitiveCount());
      EXPECT_EQ(scene.materialCount(), reference.materialCount());
      for (std::uint32_t i = 0; i < scene.primitiveCount(); ++i) {
        ASSERT_TRUE(
            scene.primitiveBounds(i).min().isApprox(reference.primitiveBounds(i).min(), 1e-12));
        ASSERT_TRUE(
            scene.primitiveBounds(i).max().isApprox(reference.primitiveBounds(i).max(), 1e-12));
      }
    }
    // A variant-0 run shorter than a lap has a world of its own (furniture along its part only):
    // the check above can fail.
    const Scene partial = buildProfileScene(profileOf(kind, 0, 12.0), 7);
    EXPECT_LT(partial.primitiveCount(), reference.primitiveCount()) << name;
  }
}

TEST(ProfileVariants, TheVariantIsAValidatedSimKeyAndIsWrittenToSimulationIni) {
  IniReader ini = IniReader::fromText("[sim]\nvariant = 2\n", "v.ini");
  EXPECT_EQ(SimOptions::load(ini).profile.variant, 2);
  IniReader none = IniReader::empty();
  EXPECT_EQ(SimOptions::load(none).profile.variant, 0);
  IniReader bad = IniReader::fromText("[sim]\nvariant = 3\n", "bad.ini");
  try {
    SimOptions::load(bad);
    ADD_FAILURE() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.ini"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("variant"), std::string::npos) << e.what();
  }
  ProfileOptions po;
  po.variant = -1;
  EXPECT_THROW(makeMotionProfile(po, bodyCam()), std::invalid_argument);

  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.profile.variant = 1;
  o.fps = 2.0;
  o.prefetch_frames = false;
  const SimulatedSequence seq(o);
  const std::string text = simulationSettingsText(seq);
  EXPECT_NE(text.find("\nvariant = 1"), std::string::npos) << text;
  IniReader again = IniReader::fromText(text, "simulation.ini");
  const SimOptions back = SimOptions::load(again);
  EXPECT_EQ(back.profile.variant, 1);
  // Regenerated from simulation.ini: the same ground truth.
  const SimulatedSequence regen(back);
  EXPECT_TRUE(
      regen.groundTruth(1003.0).T_world_body.isApprox(seq.groundTruth(1003.0).T_world_body, 1e-12));
  // Variant 0 writes no variant line: its files are the ones written before variants existed.
  o.profile.variant = 0;
  const SimulatedSequence seq0(o);
  EXPECT_EQ(simulationSettingsText(seq0).find("variant"), std::string::npos);
}

}  // namespace rgbdi::sim
