// World variation knobs of the simulator ([sim] world_seed, room_margin_m, furniture_density,
// furniture_lateral_max_m, texture_contrast, exposure_gain_amplitude, exposure_period_s): the
// defaults give today's worlds, each knob does exactly what it states, options load and validate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "rgbdi/sim/exposure.h"
#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/sim/texture.h"

namespace rgbdi::sim {
namespace {

MotionProfile worldOf(ProfileKind kind) {
  ProfileOptions o;
  o.kind = kind;
  return makeMotionProfile(o, Eigen::Isometry3d::Identity());
}

void expectSameGeometry(const Scene& a, const Scene& b) {
  ASSERT_EQ(a.primitiveCount(), b.primitiveCount());
  EXPECT_EQ(a.materialCount(), b.materialCount());
  for (std::uint32_t i = 0; i < a.primitiveCount(); ++i) {
    ASSERT_EQ(a.primitiveBounds(i).min(), b.primitiveBounds(i).min()) << i;
    ASSERT_EQ(a.primitiveBounds(i).max(), b.primitiveBounds(i).max()) << i;
  }
}

/// Horizontal distance from a point to the nearest sample of the path.
double distanceToPath(const ProfileLayout& l, const Eigen::Vector2d& p) {
  double best = INFINITY;
  for (const Eigen::Vector2d& q : l.path_xy) best = std::min(best, (q - p).norm());
  return best;
}

/// Primitives the room, ramps and platforms take: the furniture follows them.
std::uint32_t structureCount(const MotionProfile& prof) {
  ProfileSceneOptions empty;
  empty.furniture_density = 0.0;
  return buildProfileScene(prof, 7, empty).primitiveCount();
}

IniReader iniOf(const std::string& sim_lines) {
  return IniReader::fromText("[sim]\n" + sim_lines, "world.ini");
}

TEST(WorldVariation, ExplicitDefaultsGiveTodaysWorlds) {
  // Primitive counts of the four worlds (furniture along one lap) before the knobs existed
  // (sequences of every profile and variant were also compared byte for byte with that build).
  const std::vector<std::pair<std::string, std::uint32_t>> today{
      {"handheld", 35}, {"wheeled_circle", 34}, {"wheeled_slopes", 41}, {"tracked_slopes", 40}};
  IniReader ini = iniOf(
      "world_seed = 0\nroom_margin_m = 0\nfurniture_density = 1\nfurniture_lateral_max_m = 0.7\n"
      "texture_contrast = 1\n");
  const ProfileSceneOptions explicit_defaults = ProfileSceneOptions::load(ini);
  for (const auto& [name, count] : today) {
    SCOPED_TRACE(name);
    const MotionProfile prof = worldOf(parseProfileKind(name));
    const Scene implicit = buildProfileScene(prof, 7);
    const Scene loaded = buildProfileScene(prof, 7, explicit_defaults);
    EXPECT_EQ(implicit.primitiveCount(), count);
    expectSameGeometry(implicit, loaded);
  }
}

TEST(WorldVariation, DefaultSequenceFramesEqualExplicitDefaults) {
  SimOptions d;
  d.profile.kind = ProfileKind::TrackedSlopes;
  d.profile.duration_s = 12.0;
  d.fps = 2.0;
  d.prefetch_frames = false;
  IniReader ini = iniOf(
      "duration_s = 12\nfps = 2\nworld_seed = 0\nroom_margin_m = 0\nfurniture_density = 1\n"
      "furniture_lateral_max_m = 0.7\ntexture_contrast = 1\nexposure_gain_amplitude = 0\n"
      "exposure_period_s = 8\n");
  SimOptions e = SimOptions::load(ini);
  e.profile.kind = ProfileKind::TrackedSlopes;
  e.prefetch_frames = false;
  const SimulatedSequence a(d), b(e);
  expectSameGeometry(a.scene(), b.scene());
  ASSERT_EQ(a.frameCount(), b.frameCount());
  for (std::size_t i : {std::size_t{0}, a.frameCount() / 2, a.frameCount() - 1}) {
    const RgbdFrame fa = a.renderFrame(i), fb = b.renderFrame(i);
    EXPECT_EQ(cv::norm(fa.rgb, fb.rgb, cv::NORM_INF), 0.0) << i;
    EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0) << i;
  }
  for (std::size_t k = 0; k < a.imuCount(); k += 97) {
    EXPECT_EQ(a.imuSample(k).acc, b.imuSample(k).acc);
    EXPECT_EQ(a.imuSample(k).gyr, b.imuSample(k).gyr);
  }
  // simulation.ini of a default run names none of the new keys (files as before).
  const std::string settings = simulationSettingsText(a);
  for (const char* key : {"world_seed", "room_margin_m", "furniture_density",
                          "furniture_lateral_max_m", "texture_contrast", "exposure_"})
    EXPECT_EQ(settings.find(key), std::string::npos) << key;
}

TEST(WorldVariation, WorldSeedDrawsOtherFurnitureAlongTheSamePath) {
  for (const std::string& name : profileNames()) {
    SCOPED_TRACE(name);
    const MotionProfile prof = worldOf(parseProfileKind(name));
    const std::uint32_t structure = structureCount(prof);
    const Scene today = buildProfileScene(prof, 7);
    ProfileSceneOptions o;
    o.world_seed = 5;
    const Scene a = buildProfileScene(prof, 7, o), again = buildProfileScene(prof, 7, o);
    expectSameGeometry(a, again);
    // The room, ramps and platforms stay; the furniture moves.
    ASSERT_GT(a.primitiveCount(), structure + 10);
    for (std::uint32_t i = 0; i < structure; ++i) {
      EXPECT_EQ(a.primitiveBounds(i).min(), today.primitiveBounds(i).min());
      EXPECT_EQ(a.primitiveBounds(i).max(), today.primitiveBounds(i).max());
    }
    int moved = 0;
    for (std::uint32_t i = structure; i < std::min(a.primitiveCount(), today.primitiveCount()); ++i)
      moved += a.primitiveBounds(i).min() != today.primitiveBounds(i).min();
    EXPECT_GT(moved, 10);
    // Still off the corridor: every piece's centre is farther than the clearance from the path.
    for (std::uint32_t i = structure; i < a.primitiveCount(); ++i) {
      const Eigen::Vector3d c = a.primitiveBounds(i).center();
      EXPECT_GT(distanceToPath(prof.layout, c.head<2>()), prof.layout.path_clearance_m) << i;
    }
  }
}

TEST(WorldVariation, DensityZeroLeavesAnEmptyRoomAndLowDensityFewerPieces) {
  for (ProfileKind kind : {ProfileKind::Handheld, ProfileKind::WheeledCircle}) {
    // No ramps or platforms on these paths: the room's six slabs alone.
    EXPECT_EQ(structureCount(worldOf(kind)), 6u) << toString(kind);
  }
  const MotionProfile prof = worldOf(ProfileKind::TrackedSlopes);
  const std::uint32_t structure = structureCount(prof);
  // Room (6), two ramps, the platform: the profile's ground only.
  EXPECT_EQ(structure, 6u + prof.layout.ramps.size() + prof.layout.platforms.size());
  const std::uint32_t full = buildProfileScene(prof, 7).primitiveCount();
  ProfileSceneOptions half;
  half.furniture_density = 0.5;
  const std::uint32_t some = buildProfileScene(prof, 7, half).primitiveCount();
  EXPECT_GT(some, structure);
  EXPECT_LT(some - structure, full - structure);
}

TEST(WorldVariation, RoomMarginMovesEveryWallByExactlyThatMuch) {
  const MotionProfile prof = worldOf(ProfileKind::WheeledSlopes);
  const Scene today = buildProfileScene(prof, 7);
  ProfileSceneOptions o;
  o.room_margin_m = 1.25;
  const Scene big = buildProfileScene(prof, 7, o);
  // addRoom's slabs: floor, ceiling, walls -x, +x, -y, +y (0.2 m thick, outside the interior).
  const double m = o.room_margin_m;
  EXPECT_NEAR(big.primitiveBounds(2).max().x(), today.primitiveBounds(2).max().x() - m, 1e-12);
  EXPECT_NEAR(big.primitiveBounds(3).min().x(), today.primitiveBounds(3).min().x() + m, 1e-12);
  EXPECT_NEAR(big.primitiveBounds(4).max().y(), today.primitiveBounds(4).max().y() - m, 1e-12);
  EXPECT_NEAR(big.primitiveBounds(5).min().y(), today.primitiveBounds(5).min().y() + m, 1e-12);
  EXPECT_NEAR(big.primitiveBounds(2).max().x(), prof.layout.room_min.x() - m, 1e-12);
  EXPECT_NEAR(big.primitiveBounds(5).min().y(), prof.layout.room_max.y() + m, 1e-12);
  // Ceiling and floor heights kept.
  EXPECT_EQ(big.primitiveBounds(1).min().z(), today.primitiveBounds(1).min().z());
  EXPECT_EQ(big.primitiveBounds(0).max().z(), today.primitiveBounds(0).max().z());
}

TEST(WorldVariation, FurnitureLateralMaxBoundsTheFurnitureDistanceFromThePath) {
  const MotionProfile prof = worldOf(ProfileKind::WheeledCircle);
  const std::uint32_t structure = structureCount(prof);
  // A piece stands at clearance + r + lateral (r <= 0.72 m, the largest cabinet's half
  // diagonal) beside its path point, shifted up to 0.3 m along the path.
  auto farthest = [&](double lateral_max, double margin) {
    ProfileSceneOptions o;
    o.furniture_lateral_max_m = lateral_max;
    o.room_margin_m = margin;
    const Scene s = buildProfileScene(prof, 7, o);
    double far = 0.0;
    for (std::uint32_t i = structure; i < s.primitiveCount(); ++i)
      far = std::max(far, distanceToPath(prof.layout, s.primitiveBounds(i).center().head<2>()));
    return far;
  };
  const double c = prof.layout.path_clearance_m;
  const double today = farthest(0.7, 0.0);
  EXPECT_LE(today, c + 0.72 + 0.7 + 0.3);
  EXPECT_LE(farthest(0.05, 0.0), c + 0.72 + 0.05 + 0.3);
  // Far furniture needs room: with a 3 m margin some piece stands beyond today's reach.
  const double wide = farthest(3.0, 3.0);
  EXPECT_GT(wide, c + 0.72 + 0.7 + 0.3);
  EXPECT_LE(wide, c + 0.72 + 3.0 + 0.3);
}

TEST(WorldVariation, TextureContrastScalesTheDeviationFromTheMeanColour) {
  // Two levels per channel in equal numbers: the mean is exact and halving is exact.
  cv::Mat two(4, 4, CV_8UC3);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      two.at<cv::Vec3b>(y, x) = (x + y) % 2 ? cv::Vec3b(100, 20, 0) : cv::Vec3b(200, 60, 255);
  scaleTextureContrast(two, 0.5);
  EXPECT_EQ(two.at<cv::Vec3b>(0, 0), cv::Vec3b(175, 50, 191));  // 127.5 + 127.5 / 2 = 191.25
  EXPECT_EQ(two.at<cv::Vec3b>(0, 1), cv::Vec3b(125, 30, 64));   // 127.5 - 63.75 = 63.75

  // A generated texture: every texel's deviation halves (to the rounding of 0.5).
  const cv::Mat original = generateTexture(TextureStyle::Posters, 64, 0.004, 3);
  cv::Mat faint = original.clone();
  scaleTextureContrast(faint, 0.5);
  const cv::Scalar mean = cv::mean(original);
  double worst = 0.0;
  for (int y = 0; y < original.rows; ++y)
    for (int x = 0; x < original.cols; ++x)
      for (int ch = 0; ch < 3; ++ch) {
        const double o = original.at<cv::Vec3b>(y, x)[ch], f = faint.at<cv::Vec3b>(y, x)[ch];
        worst = std::max(worst, std::abs((f - mean[ch]) - 0.5 * (o - mean[ch])));
      }
  EXPECT_LE(worst, 0.5);
  cv::Mat same = original.clone();
  scaleTextureContrast(same, 1.0);
  EXPECT_EQ(cv::norm(same, original, cv::NORM_INF), 0.0);
  EXPECT_THROW(scaleTextureContrast(same, 0.0), std::invalid_argument);
  EXPECT_THROW(scaleTextureContrast(same, 1.5), std::invalid_argument);

  // In a rendered frame the texture gradients fade; the geometry stays.
  auto gradient = [](double contrast) {
    SimOptions o;
    o.profile.kind = ProfileKind::WheeledCircle;
    o.profile.duration_s = 9.0;
    o.scene.texture_contrast = contrast;
    const SimulatedSequence seq(o);
    cv::Mat rgb, depth, grey, gx;
    seq.renderIdeal(0, rgb, depth);
    cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
    cv::Sobel(grey, gx, CV_32F, 1, 0);
    return cv::mean(cv::abs(gx))[0];
  };
  const double full = gradient(1.0), faint_frame = gradient(0.3);
  EXPECT_LT(faint_frame, 0.45 * full) << full << " " << faint_frame;
}

TEST(WorldVariation, ExposureGainStaysInItsBandDeterministicallyWithItsPeriod) {
  ExposureOptions o;
  o.gain_amplitude = 0.4;
  o.period_s = 8.0;
  const ExposureGain g(o, 3), same(o, 3), other(o, 4);
  double lo = INFINITY, hi = -INFINITY, max_step = 0.0, diff = 0.0;
  int crossings = 0;
  const double dt = 0.01, duration = 2000.0;
  double prev = g.gain(0.0);
  for (double t = dt; t <= duration; t += dt) {
    const double v = g.gain(t);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    max_step = std::max(max_step, std::abs(v - prev));
    crossings += (v - 1.0) * (prev - 1.0) < 0.0;
    EXPECT_EQ(v, same.gain(t));
    diff = std::max(diff, std::abs(v - other.gain(t)));
    prev = v;
  }
  EXPECT_GE(lo, 0.6);
  EXPECT_LE(hi, 1.4);
  EXPECT_LT(lo, 0.65);  // the band is used
  EXPECT_GT(hi, 1.35);
  EXPECT_GT(diff, 0.2);  // another seed, another drift
  // Smooth: the steepest slope of the quintic blend (15/8) between knots 2 s apart whose
  // values differ by at most 2 amplitudes.
  EXPECT_LE(max_step / dt, 1.875 * 2.0 * 0.4 / 2.0 + 1e-6);
  // Twice per period on average, like a sinusoid: 500 expected in 2000 s (std 16 for
  // independent knots).
  EXPECT_GT(crossings, 450);
  EXPECT_LT(crossings, 550);
  const ExposureGain off(ExposureOptions{}, 3);
  EXPECT_TRUE(off.constant());
  EXPECT_EQ(off.gain(12.3), 1.0);
  ExposureOptions bad = o;
  bad.gain_amplitude = 0.95;
  EXPECT_THROW(ExposureGain(bad, 1), std::invalid_argument);
  bad = o;
  bad.period_s = 0.0;
  EXPECT_THROW(ExposureGain(bad, 1), std::invalid_argument);
}

TEST(WorldVariation, ExposureGainScalesTheColourBeforeTheNoiseAndLeavesDepth) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.fps = 2.0;
  o.prefetch_frames = false;
  o.color_noise.sigma = 0.0;
  const SimulatedSequence plain(o);
  o.exposure.gain_amplitude = 0.5;
  o.exposure.period_s = 4.0;
  const SimulatedSequence drifting(o);
  const ExposureGain g(o.exposure, o.seed);
  for (std::size_t i = 0; i < drifting.frameCount(); i += 3) {
    const RgbdFrame a = plain.renderFrame(i), b = drifting.renderFrame(i);
    cv::Mat expected;
    a.rgb.convertTo(expected, CV_8UC3, g.gain(static_cast<double>(i) / o.fps));
    EXPECT_EQ(cv::norm(b.rgb, expected, cv::NORM_INF), 0.0) << i;
    EXPECT_EQ(cv::norm(a.depth, b.depth, cv::NORM_INF), 0.0) << i;
  }
}

TEST(WorldVariation, KeysLoadValidateAndRoundTripThroughSimulationIni) {
  IniReader ini = iniOf(
      "world_seed = 12\nroom_margin_m = 2.5\nfurniture_density = 0.4\n"
      "furniture_lateral_max_m = 1.5\ntexture_contrast = 0.3\nexposure_gain_amplitude = 0.2\n"
      "exposure_period_s = 5\nduration_s = 9\n");
  SimOptions o = SimOptions::load(ini);
  EXPECT_EQ(o.scene.world_seed, 12u);
  EXPECT_EQ(o.scene.room_margin_m, 2.5);
  EXPECT_EQ(o.scene.furniture_density, 0.4);
  EXPECT_EQ(o.scene.furniture_lateral_max_m, 1.5);
  EXPECT_EQ(o.scene.texture_contrast, 0.3);
  EXPECT_EQ(o.exposure.gain_amplitude, 0.2);
  EXPECT_EQ(o.exposure.period_s, 5.0);
  const SimulatedSequence seq(o);
  IniReader again = IniReader::fromText(simulationSettingsText(seq), "simulation.ini");
  const SimOptions r = SimOptions::load(again);
  EXPECT_EQ(r.scene.world_seed, 12u);
  EXPECT_EQ(r.scene.room_margin_m, 2.5);
  EXPECT_EQ(r.scene.furniture_density, 0.4);
  EXPECT_EQ(r.scene.furniture_lateral_max_m, 1.5);
  EXPECT_EQ(r.scene.texture_contrast, 0.3);
  EXPECT_EQ(r.exposure.gain_amplitude, 0.2);
  EXPECT_EQ(r.exposure.period_s, 5.0);

  for (const std::string bad :
       {"world_seed = -1", "room_margin_m = -0.1", "room_margin_m = 11", "furniture_density = 1.5",
        "furniture_lateral_max_m = 0.01", "texture_contrast = 0", "texture_contrast = 1.2",
        "exposure_gain_amplitude = 0.95", "exposure_period_s = 0"}) {
    IniReader b = iniOf(bad + "\n");
    const std::string key = bad.substr(0, bad.find(' '));
    try {
      SimOptions::load(b);
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("world.ini"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rgbdi::sim
