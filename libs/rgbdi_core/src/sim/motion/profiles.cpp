#include "rgbdi/sim/profiles.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "rgbdi/sim/motion_ground_path.h"
#include "rgbdi/sim/motion_smooth_steps.h"
#include "sim/motion/path_following_trajectory.h"
#include "sim/motion/tones.h"

namespace rgbdi::sim {
namespace {

// The motion is the same for every noise seed; this seed only fixes the vibration phases.
constexpr std::uint64_t kMotionPhaseSeed = 0x6a09e667f3bcc909ULL;
constexpr double kDeg = M_PI / 180.0;

// ---------------------------------------------------------------- speed over time
struct Timeline {
  double rest_start = 2.0, accel = 2.5, decel = 2.5, rest_end = 1.0, duration = 0.0;
  double movingTime() const { return duration - rest_start - rest_end; }
  /// Distance per m/s of cruise speed: accelerating over T with a symmetric smooth step covers
  /// exactly v T / 2.
  double effectiveTime() const { return movingTime() - 0.5 * (accel + decel); }
};

/// A temporary speed increase (the paper's "intermittent high speed phases").
struct Burst {
  double start = 0.0, length = 0.0, dv = 0.0;
  static constexpr double kRamp = 1.0;  ///< [s] smooth-step width of the speed change
};

SmoothSteps makeSpeedProfile(const Timeline& tl, double v, const std::vector<Burst>& bursts) {
  SmoothSteps speed;
  speed.addStep(tl.rest_start, tl.accel, v);
  for (const Burst& b : bursts) {
    speed.addStep(b.start, Burst::kRamp, b.dv);
    speed.addStep(b.start + b.length, Burst::kRamp, -b.dv);
  }
  speed.addStep(tl.duration - tl.rest_end - tl.decel, tl.decel, -v);
  return speed;
}

double burstDistance(const std::vector<Burst>& bursts) {
  double d = 0.0;
  for (const Burst& b : bursts) d += b.dv * b.length;
  return d;
}

/// High-speed phases every 20 s while cruising, as long as they end 3 s before braking.
std::vector<Burst> fastBursts(const Timeline& tl) {
  std::vector<Burst> bursts;
  const double first = tl.rest_start + tl.accel + 8.0;
  const double last_end = tl.duration - tl.rest_end - tl.decel - 3.0;
  for (double t = first; t + 5.0 + Burst::kRamp <= last_end; t += 20.0)
    bursts.push_back(Burst{t, 5.0, 0.35});
  return bursts;
}

// ---------------------------------------------------------------- closed loops
/// A straight followed by a turn of `turn_rad` at radius `radius`, entered and left over
/// `transition` metres of smoothly varying curvature.
struct LoopSegment {
  double straight = 0.0, turn_rad = 0.0, radius = 1.0, transition = 0.5;
  double length() const { return straight + turn_rad * radius + transition; }
};

struct LoopPlan {
  SmoothSteps curvature;
  double lap = 0.0;
  std::vector<double> segment_start;  ///< arc length where each segment's straight begins (lap 0)
};

/// Curvature profile repeating `segments` until `total_length` is covered. A turn is an up-step
/// of the curvature to 1/radius and a down-step turn_rad * radius later (same width), which
/// turns the heading by exactly turn_rad.
LoopPlan planLoop(const std::vector<LoopSegment>& segments, double total_length) {
  LoopPlan plan;
  for (const LoopSegment& seg : segments) {
    plan.segment_start.push_back(plan.lap);
    plan.lap += seg.length();
  }
  for (double lap_start = 0.0; lap_start < total_length; lap_start += plan.lap) {
    double s = lap_start;
    for (const LoopSegment& seg : segments) {
      const double turn_start = s + seg.straight;
      const double k = 1.0 / seg.radius;
      plan.curvature.addStep(turn_start, seg.transition, k);
      plan.curvature.addStep(turn_start + seg.turn_rad * seg.radius, seg.transition, -k);
      s += seg.length();
    }
  }
  return plan;
}

// ---------------------------------------------------------------- slopes along the path
struct SymmetricRampFeature {
  double foot = 0.0, run = 1.0, height = 0.1;  ///< lap-relative arc length of the foot [m]
};
struct PlatformFeature {
  double foot = 0.0, ramp_run = 0.8, top = 1.4, height = 0.08, drop_run = 0.16;
  double edge() const { return foot + ramp_run + top; }
};

/// Adds a change of slope by `delta` centred at s (rounded over `width`).
void slopeChange(SmoothSteps& slope, double s, double width, double delta) {
  slope.addStep(s - 0.5 * width, width, delta);
}

// ---------------------------------------------------------------- helpers
Eigen::AlignedBox2d pathBounds(const GroundPath& path, double from, double to) {
  Eigen::AlignedBox2d box;
  for (double s = from; s <= to; s += 0.05) box.extend(path.xy(s));
  return box;
}

std::vector<Eigen::Vector2d> samplePath(const GroundPath& path, double length) {
  std::vector<Eigen::Vector2d> xy;
  const int n = static_cast<int>(std::ceil(length / 0.1));
  for (int i = 0; i <= n; ++i) xy.push_back(path.xy(std::min(length, 0.1 * i)));
  return xy;
}

ToneSum mergeTones(const ToneSum& a, const ToneSum& b) {
  std::vector<Tone> t = a.tones();
  t.insert(t.end(), b.tones().begin(), b.tones().end());
  return ToneSum(std::move(t));
}

/// Vibration tones with the given total (vector) RMS of acceleration and angular rate, split
/// over the axes by fixed weights (vertical bounce dominates, as on a real robot).
void addVibration(PathFollowingMotion& m, double acc_rms, double gyr_rms, double f_min,
                  double f_max) {
  const Eigen::Vector3d wt = Eigen::Vector3d(0.45, 0.35, 0.82).normalized();
  const Eigen::Vector3d wr = Eigen::Vector3d(0.55, 0.70, 0.45).normalized();
  const int tones = 8;
  for (int i = 0; i < 3; ++i) {
    const auto a = static_cast<size_t>(i);
    m.translation[a] =
        mergeTones(m.translation[a], bandTones(acc_rms * wt[i], 2, f_min, f_max, tones,
                                               0.15 + 0.25 * i, kMotionPhaseSeed + 11 * a));
    m.rotation[a] =
        mergeTones(m.rotation[a], bandTones(gyr_rms * wr[i], 1, f_min, f_max, tones,
                                            0.27 + 0.25 * i, kMotionPhaseSeed + 101 * a + 7));
  }
}

void addJitter(PathFollowingMotion& m, double rms_rad) {
  const double weight[3] = {1.0, 1.0, 0.5};
  for (int i = 0; i < 3; ++i) {
    const auto a = static_cast<size_t>(i);
    m.rotation[a] = mergeTones(
        m.rotation[a],
        bandTones(rms_rad * weight[i], 0, 1.0, 6.0, 5, 0.2 + 0.3 * i, kMotionPhaseSeed + 1009 * a));
  }
}

/// Body origin height above the ground that puts the camera at camera_height (level body).
double mountHeight(double camera_height, const Eigen::Isometry3d& T_body_cam) {
  return camera_height - T_body_cam.translation().z();
}

/// Where a variant starts on the profile's closed path: lap-relative arc length [m] and
/// direction. Variant 0 is {0, forward}.
struct VariantStart {
  double s = 0.0;
  bool reverse = false;
};

/// Arc length of the (lap-periodic) base path where the motion starts: a reversed run goes
/// back from a start whole laps further on, so that it never needs the path before s = 0.
double baseStart(const VariantStart& v, double lap, double length) {
  return v.reverse ? v.s + std::ceil(length / lap) * lap : v.s;
}

/// Length the base path must cover for a run of `length` metres from `v`.
double baseLength(const VariantStart& v, double lap, double length) {
  return v.reverse ? baseStart(v, lap, length) : v.s + length;
}

void startAt(PathFollowingMotion& m, const VariantStart& v, double lap, double length) {
  m.path_start_m = baseStart(v, lap, length);
  m.path_reverse = v.reverse;
}

VariantStart pick(int variant, const VariantStart& v1, const VariantStart& v2) {
  return variant == 1 ? v1 : (variant == 2 ? v2 : VariantStart{});
}

struct ProfileParts {
  Timeline timeline;
  double cruise = 0.0;
  std::vector<Burst> bursts;
};

/// Resolves cruise speed and duration from the options: a default length (circle: 3 laps) or a
/// default (length, duration) pair (wheeled_slopes presets) fixes what the user did not give.
ProfileParts resolveTiming(const ProfileOptions& o, double default_speed, double default_duration,
                           double default_length, double accel, bool fast_bursts) {
  ProfileParts p;
  p.timeline.rest_start = o.rest_start_s;
  p.timeline.rest_end = o.rest_end_s;
  p.timeline.accel = accel;
  p.timeline.decel = accel;
  const double overhead = o.rest_start_s + o.rest_end_s + accel;  // duration not at full distance
  if (o.speed_m_s > 0.0) {
    p.cruise = o.speed_m_s;
  } else if (default_length > 0.0 && default_duration > 0.0) {
    p.timeline.duration = default_duration;
    if (fast_bursts) p.bursts = fastBursts(p.timeline);
    p.cruise = (default_length - burstDistance(p.bursts)) / p.timeline.effectiveTime();
  } else {
    p.cruise = default_speed;
  }
  if (o.duration_s > 0.0)
    p.timeline.duration = o.duration_s;
  else if (default_duration > 0.0)
    p.timeline.duration = default_duration;
  else
    p.timeline.duration = overhead + default_length / p.cruise;

  const double min_duration = o.rest_start_s + o.rest_end_s + 2.0 * accel + 1.0;
  if (p.timeline.duration < min_duration) {
    std::ostringstream os;
    os << "profile " << toString(o.kind) << ": duration " << p.timeline.duration
       << " s is too short; it needs at least " << min_duration << " s (rest " << o.rest_start_s
       << " s + acceleration " << accel << " s + 1 s moving + braking " << accel << " s + rest "
       << o.rest_end_s << " s)";
    throw std::invalid_argument(os.str());
  }
  p.bursts = fast_bursts ? fastBursts(p.timeline) : std::vector<Burst>{};
  return p;
}

/// Builds the path centred on the origin (the loop's bounding box centre). A variant's path is
/// centred on the whole lap, as the world's (a default-duration variant 0, which covers a lap) is:
/// centred on the part a short run covers, it would lie beside the world's path and drive
/// through the world's furniture. planLoop and the slopes always cover the first lap.
GroundPath centredPath(const SmoothSteps& curvature, const SmoothSteps& slope, double lap,
                       double length, bool variant) {
  const double centred_on = variant ? lap : std::min(lap, length);
  const GroundPath probe(curvature, slope, Eigen::Vector2d::Zero(), 0.0, 0.0,
                         std::max(length, centred_on));
  const Eigen::Vector2d c = pathBounds(probe, 0.0, centred_on).center();
  return GroundPath(curvature, slope, -c, 0.0, 0.0, length);
}

MotionProfile finish(ProfileKind kind, const ProfileParts& parts, GroundPath path,
                     PathFollowingMotion motion, double lap, double room_margin, double ceiling,
                     double clearance) {
  MotionProfile prof;
  prof.kind = kind;
  prof.cruise_speed_m_s = parts.cruise;
  prof.path_length_m = motion.speed.integral(parts.timeline.duration);
  prof.lap_length_m = lap;
  prof.moving_start_s = parts.timeline.rest_start;
  prof.moving_end_s = parts.timeline.duration - parts.timeline.rest_end;
  prof.cruise_start_s = parts.timeline.rest_start + parts.timeline.accel;
  prof.cruise_end_s = prof.moving_end_s - parts.timeline.decel;
  const Eigen::AlignedBox2d box = pathBounds(path, 0.0, std::min(lap, prof.path_length_m));
  prof.layout.room_min =
      Eigen::Vector3d(box.min().x() - room_margin, box.min().y() - room_margin, 0.0);
  prof.layout.room_max =
      Eigen::Vector3d(box.max().x() + room_margin, box.max().y() + room_margin, ceiling);
  prof.layout.path_xy = samplePath(path, prof.path_length_m);
  prof.layout.path_clearance_m = clearance;
  prof.trajectory = std::make_shared<PathFollowingTrajectory>(std::move(path), std::move(motion));
  return prof;
}

// ---------------------------------------------------------------- the four profiles
double presetFactor(SpeedPreset s) {
  return s == SpeedPreset::Slow ? 0.6 : (s == SpeedPreset::Fast ? 1.4 : 1.0);
}

MotionProfile wheeledCircle(const ProfileOptions& o, const Eigen::Isometry3d& T_body_cam) {
  const double radius = 2.0, laps = 3.0;
  const ProfileParts parts =
      resolveTiming(o, 0.4 * presetFactor(o.speed), 0.0, laps * 2.0 * M_PI * radius, 2.5, false);
  PathFollowingMotion m;
  m.speed = makeSpeedProfile(parts.timeline, parts.cruise, parts.bursts);
  m.cruise_speed = parts.cruise;
  m.duration = parts.timeline.duration;
  m.mount_height = mountHeight(o.wheeled_camera_height_m, T_body_cam);
  addVibration(m, o.wheeled_vibration_acc_rms, o.wheeled_vibration_gyr_rms, o.vibration_band_min_hz,
               o.vibration_band_max_hz);
  const double length = m.speed.integral(m.duration);
  // Variants: clockwise from the opposite side (-r, 0); counter-clockwise from (0, r).
  const double lap = 2.0 * M_PI * radius;
  const VariantStart v = pick(o.variant, {0.5 * lap, true}, {0.25 * lap, false});
  startAt(m, v, lap, length);
  // Counter-clockwise around the origin, starting on the +x axis heading +y.
  GroundPath path(SmoothSteps(1.0 / radius), SmoothSteps(), Eigen::Vector2d(radius, 0.0), 0.0,
                  0.5 * M_PI, baseLength(v, lap, length) + 1.0);
  return finish(ProfileKind::WheeledCircle, parts, std::move(path), std::move(m),
                2.0 * M_PI * radius, 2.0, 3.0, 0.45);
}

MotionProfile wheeledSlopes(const ProfileOptions& o, const Eigen::Isometry3d& T_body_cam) {
  // The paper's runs: slow 31 m / 148 s, normal 32 m / 74 s, fast 48 m / 99 s.
  double L = 32.0, D = 74.0;
  if (o.speed == SpeedPreset::Slow) L = 31.0, D = 148.0;
  if (o.speed == SpeedPreset::Fast) L = 48.0, D = 99.0;
  const ProfileParts parts = resolveTiming(o, 0.0, D, L, 2.5, o.speed == SpeedPreset::Fast);
  PathFollowingMotion m;
  m.speed = makeSpeedProfile(parts.timeline, parts.cruise, parts.bursts);
  m.cruise_speed = parts.cruise;
  m.duration = parts.timeline.duration;
  m.mount_height = mountHeight(o.wheeled_camera_height_m, T_body_cam);
  addVibration(m, o.wheeled_vibration_acc_rms, o.wheeled_vibration_gyr_rms, o.vibration_band_min_hz,
               o.vibration_band_max_hz);
  const double run_length = m.speed.integral(m.duration) + 1.0;

  // Racetrack: 6 m straights, 180-degree turns of radius 1.2 m.
  const LoopSegment seg{6.0, M_PI, 1.2, 0.6};
  // Variants start on flat ground: backwards from the end of the second straight (towards its
  // ramp), forwards from the end of the first straight (into the first turn).
  const VariantStart v = pick(o.variant, {seg.length() + 5.0, true}, {5.0, false});
  startAt(m, v, 2.0 * seg.length(), run_length);
  const double length = baseLength(v, 2.0 * seg.length(), run_length);
  const LoopPlan loop = planLoop({seg, seg}, length);
  const std::vector<SymmetricRampFeature> ramps{{2.0, 1.0, 0.12},
                                                {loop.segment_start[1] + 1.5, 0.9, 0.10}};
  const double transition = 0.3;  // [m] rounding of the ramp edges (about a wheelbase)
  SmoothSteps slope;
  for (double lap = 0.0; lap < length; lap += loop.lap) {
    for (const SymmetricRampFeature& r : ramps) {
      const double m_r = r.height / r.run;
      slopeChange(slope, lap + r.foot, transition, m_r);
      slopeChange(slope, lap + r.foot + r.run, transition, -2.0 * m_r);
      slopeChange(slope, lap + r.foot + 2.0 * r.run, transition, m_r);
    }
  }
  GroundPath path = centredPath(loop.curvature, slope, loop.lap, length, o.variant != 0);
  const double width = 1.2;
  std::vector<RampLayout> ramp_layout;
  for (const SymmetricRampFeature& r : ramps)
    ramp_layout.push_back(
        RampLayout{path.xy(r.foot), path.xy(r.foot + 2.0 * r.run), width, r.height, true});
  MotionProfile prof = finish(ProfileKind::WheeledSlopes, parts, std::move(path), std::move(m),
                              loop.lap, 2.0, 3.0, 0.45);
  prof.layout.ramps = ramp_layout;
  return prof;
}

MotionProfile trackedSlopes(const ProfileOptions& o, const Eigen::Isometry3d& T_body_cam) {
  const ProfileParts parts = resolveTiming(o, 0.3 * presetFactor(o.speed), 65.0, 0.0, 2.5, false);
  PathFollowingMotion m;
  m.speed = makeSpeedProfile(parts.timeline, parts.cruise, parts.bursts);
  m.cruise_speed = parts.cruise;
  m.duration = parts.timeline.duration;
  m.mount_height = mountHeight(o.tracked_camera_height_m, T_body_cam);
  addVibration(m, o.tracked_vibration_acc_rms, o.tracked_vibration_gyr_rms, o.vibration_band_min_hz,
               o.vibration_band_max_hz);
  addJitter(m, o.tracked_jitter_deg * kDeg);
  const double run_length = m.speed.integral(m.duration) + 1.0;

  // Racetrack with 5 m straights and 1 m turns: an up-down ramp on the first straight, a
  // platform reached by a ramp and left over an 8 cm step drop on the second.
  const LoopSegment seg{5.0, M_PI, 1.0, 0.5};
  // Variants start on flat ground: backwards from the end of the second straight (climbing the
  // 8 cm step onto the platform, down its ramp), forwards from the end of the first straight.
  const VariantStart v = pick(o.variant, {seg.length() + 4.5, true}, {4.0, false});
  startAt(m, v, 2.0 * seg.length(), run_length);
  const double length = baseLength(v, 2.0 * seg.length(), run_length);
  const LoopPlan loop = planLoop({seg, seg}, length);
  const SymmetricRampFeature ramp{1.2, 0.8, 0.10};
  const PlatformFeature platform{loop.segment_start[1] + 0.6, 0.8, 1.4, 0.08, 0.16};
  const double transition = 0.25, drop_transition = 0.08;
  SmoothSteps slope;
  for (double lap = 0.0; lap < length; lap += loop.lap) {
    const double m_r = ramp.height / ramp.run;
    slopeChange(slope, lap + ramp.foot, transition, m_r);
    slopeChange(slope, lap + ramp.foot + ramp.run, transition, -2.0 * m_r);
    slopeChange(slope, lap + ramp.foot + 2.0 * ramp.run, transition, m_r);
    const double m_p = platform.height / platform.ramp_run;
    slopeChange(slope, lap + platform.foot, transition, m_p);
    slopeChange(slope, lap + platform.foot + platform.ramp_run, transition, -m_p);
    // The drop: the tracks tip over the edge and land drop_run further on.
    const double m_d = platform.height / platform.drop_run;
    slopeChange(slope, lap + platform.edge(), drop_transition, -m_d);
    slopeChange(slope, lap + platform.edge() + platform.drop_run, drop_transition, m_d);
  }
  GroundPath path = centredPath(loop.curvature, slope, loop.lap, length, o.variant != 0);
  const double width = 1.0;
  MotionProfile prof =
      finish(ProfileKind::TrackedSlopes, parts, path, std::move(m), loop.lap, 1.8, 3.0, 0.45);
  prof.layout.ramps.push_back(RampLayout{path.xy(ramp.foot), path.xy(ramp.foot + 2.0 * ramp.run),
                                         width, ramp.height, true});
  prof.layout.ramps.push_back(RampLayout{path.xy(platform.foot),
                                         path.xy(platform.foot + platform.ramp_run), width,
                                         platform.height, false});
  const Eigen::Vector2d top_a = path.xy(platform.foot + platform.ramp_run);
  const Eigen::Vector2d top_b = path.xy(platform.edge());
  const Eigen::Vector2d dir = top_b - top_a;
  prof.layout.platforms.push_back(PlatformLayout{0.5 * (top_a + top_b),
                                                 Eigen::Vector2d(dir.norm(), width),
                                                 std::atan2(dir.y(), dir.x()), platform.height});
  return prof;
}

MotionProfile handheld(const ProfileOptions& o, const Eigen::Isometry3d& T_body_cam) {
  const ProfileParts parts = resolveTiming(o, 0.7 * presetFactor(o.speed), 40.0, 0.0, 2.0, false);
  PathFollowingMotion m;
  m.speed = makeSpeedProfile(parts.timeline, parts.cruise, parts.bursts);
  m.cruise_speed = parts.cruise;
  m.duration = parts.timeline.duration;
  m.mount_height = mountHeight(o.handheld_camera_height_m, T_body_cam);
  // Walking (1.8 steps/s: bounce at 1.8 Hz, sway at 0.9 Hz) and slow hand/head motion; yaw
  // looks around by up to ~30 degrees, pitch and roll by ~10 degrees.
  m.translation[0] = ToneSum({{0.05, 0.21, 0.3}, {0.010, 1.8, 1.1}});
  m.translation[1] = ToneSum({{0.06, 0.17, 2.0}, {0.025, 0.9, 0.4}});
  m.translation[2] = ToneSum({{0.08, 0.07, 0.9}, {0.03, 0.29, 2.6}, {0.025, 1.8, 0.0}});
  m.rotation[0] = ToneSum({{0.10, 0.11, 0.5}, {0.05, 0.39, 1.7}, {0.02, 0.9, 2.2}});
  m.rotation[1] = ToneSum({{0.12, 0.13, 1.3}, {0.06, 0.47, 0.2}, {0.015, 1.8, 0.7}});
  m.rotation[2] = ToneSum({{0.35, 0.09, 0.0}, {0.15, 0.31, 2.9}, {0.02, 0.9, 1.4}});
  m.pitch_bias = 0.08;  // camera held slightly down
  const double run_length = m.speed.integral(m.duration) + 1.0;

  // Rounded rectangle around a table: 3.0 m and 1.6 m sides, 90-degree turns of radius 0.9 m.
  const LoopSegment a{3.0, 0.5 * M_PI, 0.9, 0.4}, b{1.6, 0.5 * M_PI, 0.9, 0.4};
  // Variants: backwards from the middle of the opposite long side, forwards from the middle of
  // the first short side.
  const double lap = 2.0 * (a.length() + b.length());
  const VariantStart v =
      pick(o.variant, {a.length() + b.length() + 1.5, true}, {a.length() + 0.8, false});
  startAt(m, v, lap, run_length);
  const double length = baseLength(v, lap, run_length);
  const LoopPlan loop = planLoop({a, b, a, b}, length);
  GroundPath path = centredPath(loop.curvature, SmoothSteps(), loop.lap, length, o.variant != 0);
  return finish(ProfileKind::Handheld, parts, std::move(path), std::move(m), loop.lap, 1.6, 2.8,
                0.45);
}

}  // namespace

const std::vector<std::string>& profileNames() {
  static const std::vector<std::string> names{"handheld", "wheeled_circle", "wheeled_slopes",
                                              "tracked_slopes"};
  return names;
}

std::string toString(ProfileKind kind) {
  if (kind == ProfileKind::Recorded) return "recorded";
  return profileNames()[static_cast<size_t>(kind)];
}

ProfileKind parseProfileKind(const std::string& name) {
  const auto& names = profileNames();
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<ProfileKind>(i);
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown profile '" + name + "' (valid: " + list + ")");
}

std::string toString(SpeedPreset speed) {
  return speed == SpeedPreset::Slow ? "slow" : (speed == SpeedPreset::Fast ? "fast" : "normal");
}

SpeedPreset parseSpeedPreset(const std::string& name) {
  if (name == "slow") return SpeedPreset::Slow;
  if (name == "normal") return SpeedPreset::Normal;
  if (name == "fast") return SpeedPreset::Fast;
  throw std::invalid_argument("unknown speed '" + name + "' (valid: slow, normal, fast)");
}

ProfileOptions ProfileOptions::load(IniReader& ini) {
  ProfileOptions o;
  const std::string s = "sim";
  o.speed =
      parseSpeedPreset(ini.getEnum(s, "speed", toString(o.speed), {"slow", "normal", "fast"}));
  o.duration_s = ini.getDouble(s, "duration_s", o.duration_s, 0.0, 86400.0);
  o.speed_m_s = ini.getDouble(s, "speed_m_s", o.speed_m_s, 0.0, 5.0);
  o.rest_start_s = ini.getDouble(s, "rest_start_s", o.rest_start_s, 0.0, 60.0);
  o.rest_end_s = ini.getDouble(s, "rest_end_s", o.rest_end_s, 0.0, 60.0);
  o.wheeled_vibration_acc_rms =
      ini.getDouble(s, "wheeled_vibration_acc_rms", o.wheeled_vibration_acc_rms, 0.0, 20.0);
  o.wheeled_vibration_gyr_rms =
      ini.getDouble(s, "wheeled_vibration_gyr_rms", o.wheeled_vibration_gyr_rms, 0.0, 2.0);
  o.tracked_vibration_acc_rms =
      ini.getDouble(s, "tracked_vibration_acc_rms", o.tracked_vibration_acc_rms, 0.0, 20.0);
  o.tracked_vibration_gyr_rms =
      ini.getDouble(s, "tracked_vibration_gyr_rms", o.tracked_vibration_gyr_rms, 0.0, 2.0);
  o.tracked_jitter_deg = ini.getDouble(s, "tracked_jitter_deg", o.tracked_jitter_deg, 0.0, 5.0);
  o.vibration_band_min_hz =
      ini.getDouble(s, "vibration_band_min_hz", o.vibration_band_min_hz, 1.0, 90.0);
  o.vibration_band_max_hz = ini.getDouble(s, "vibration_band_max_hz", o.vibration_band_max_hz,
                                          o.vibration_band_min_hz, 90.0);
  o.wheeled_camera_height_m =
      ini.getDouble(s, "wheeled_camera_height_m", o.wheeled_camera_height_m, 0.05, 2.0);
  o.tracked_camera_height_m =
      ini.getDouble(s, "tracked_camera_height_m", o.tracked_camera_height_m, 0.05, 2.0);
  o.handheld_camera_height_m =
      ini.getDouble(s, "handheld_camera_height_m", o.handheld_camera_height_m, 0.3, 2.5);
  o.variant = ini.getInt(s, "variant", o.variant, 0, kProfileVariants - 1);
  return o;
}

ProfileOptions worldOptions(const ProfileOptions& options) {
  ProfileOptions w;
  w.kind = options.kind;
  w.speed = options.speed;
  return w;
}

MotionProfile makeMotionProfile(const ProfileOptions& options,
                                const Eigen::Isometry3d& T_body_cam) {
  if (options.variant < 0 || options.variant >= kProfileVariants)
    throw std::invalid_argument("profile " + toString(options.kind) + ": variant " +
                                std::to_string(options.variant) + " does not exist (valid: 0 to " +
                                std::to_string(kProfileVariants - 1) + ")");
  MotionProfile prof;
  switch (options.kind) {
    case ProfileKind::Handheld:
      prof = handheld(options, T_body_cam);
      break;
    case ProfileKind::WheeledCircle:
      prof = wheeledCircle(options, T_body_cam);
      break;
    case ProfileKind::WheeledSlopes:
      prof = wheeledSlopes(options, T_body_cam);
      break;
    case ProfileKind::TrackedSlopes:
      prof = trackedSlopes(options, T_body_cam);
      break;
    case ProfileKind::Recorded:
      throw std::invalid_argument(
          "makeMotionProfile: a recorded motion comes from makeRecordedMotion (recorded_motion.h)");
    default:
      throw std::invalid_argument("makeMotionProfile: unknown profile kind");
  }
  // A variant lives in the world of the profile's own path: the scene is built from that.
  if (options.variant != 0)
    prof.layout = makeMotionProfile(worldOptions(options), T_body_cam).layout;
  return prof;
}

}  // namespace rgbdi::sim
