// Perceptual aliasing: with RoomStyles::aliased_x_walls / [sim] aliased_walls the two end walls
// of a room look the same from half-turned viewpoints; without it they differ.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/renderer.h"
#include "rgbdi/sim/scene.h"
#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {
namespace {

// Optical frame (x right, y down, z forward) of a camera at `eye` looking horizontally along yaw.
Eigen::Isometry3d lookFrom(const Eigen::Vector3d& eye, double yaw) {
  Eigen::Matrix3d R_body_cam;
  R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_body_cam;
  T.translation() = eye;
  return T;
}

/// The pose turned by half a turn about the vertical line through centre_xy.
Eigen::Isometry3d halfTurn(const Eigen::Isometry3d& T_world_cam, const Eigen::Vector2d& centre_xy) {
  const Eigen::Vector3d c(centre_xy.x(), centre_xy.y(), 0.0);
  const Eigen::Isometry3d R(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  return Eigen::Translation3d(c) * R * Eigen::Translation3d(-c) * T_world_cam;
}

struct Pair {
  cv::Mat rgb_a, rgb_b, depth_a, depth_b;
};

/// A room of 6 x 4 x 3 m (centre (0.5, -0.5)) rendered from a camera 1.5 m in front of the -x
/// wall facing it, and from the half-turned pose facing the +x wall. The light has no x
/// component, so both walls are lit alike.
Pair renderEndWalls(bool aliased) {
  Scene scene(11);
  RoomStyles styles;
  styles.aliased_x_walls = aliased;
  scene.addRoom({-2.5, -2.5, 0.0}, {3.5, 1.5, 3.0}, styles);
  scene.build();
  RenderOptions ro;
  ro.light_dir_world = Eigen::Vector3d(0.0, 0.3, 0.9);
  const Renderer renderer(scene, CameraOptions().camera, ro);
  const Eigen::Isometry3d T_a = lookFrom({-1.0, -0.2, 1.5}, M_PI);
  const Eigen::Isometry3d T_b = halfTurn(T_a, {0.5, -0.5});
  EXPECT_NEAR(T_b.translation().x(), 2.0, 1e-12);
  EXPECT_NEAR(T_b.translation().y(), -0.8, 1e-12);
  Pair p;
  renderer.render(T_a, p.rgb_a, p.depth_a);
  renderer.render(T_b, p.rgb_b, p.depth_b);
  return p;
}

double meanAbsDiff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / a.channels();
}

TEST(RenderAliasing, AliasedEndWallsLookTheSameFromHalfTurnedViewpoints) {
  const Pair p = renderEndWalls(true);
  // The whole view is wall 1.5 m away (the floor and ceiling are outside the field of view).
  double dmin, dmax;
  cv::minMaxLoc(p.depth_a, &dmin, &dmax);
  EXPECT_NEAR(dmin, 1.5, 1e-6);
  EXPECT_NEAR(dmax, 1.5, 1e-6);
  cv::Mat depth_diff;
  cv::absdiff(p.depth_a, p.depth_b, depth_diff);
  cv::minMaxLoc(depth_diff, nullptr, &dmax);
  EXPECT_LT(dmax, 1e-5);
  // Texture coordinates of the two walls agree to rounding: at most one grey level apart.
  cv::Mat diff;
  cv::absdiff(p.rgb_a, p.rgb_b, diff);
  cv::minMaxLoc(diff.reshape(1), nullptr, &dmax);
  EXPECT_LE(dmax, 1.0);
  EXPECT_LT(meanAbsDiff(p.rgb_a, p.rgb_b), 0.01);
  // ... and the image is textured (not a flat colour that would trivially agree).
  cv::Scalar mean, stddev;
  cv::meanStdDev(p.rgb_a.reshape(1), mean, stddev);
  EXPECT_GT(stddev[0], 20.0);
}

TEST(RenderAliasing, WithoutTheOptionTheEndWallsDiffer) {
  const Pair p = renderEndWalls(false);
  EXPECT_GT(meanAbsDiff(p.rgb_a, p.rgb_b), 20.0);
}

TEST(RenderAliasing, TheProfileOptionAliasesTheEndWallsAndNothingElse) {
  ProfileOptions po;
  po.kind = ProfileKind::Handheld;
  const MotionProfile prof = makeMotionProfile(po, ExtrinsicOptions().T_body_cam);
  const Scene plain = buildProfileScene(prof, 4);
  ProfileSceneOptions so;
  so.aliased_walls = true;
  const Scene aliased = buildProfileScene(prof, 4, so);
  ASSERT_EQ(plain.materialCount(), aliased.materialCount());
  const Eigen::Vector3d lo = prof.layout.room_min, hi = prof.layout.room_max;
  const double cy = 0.5 * (lo.y() + hi.y());
  // Rays from 2 cm in front of each wall onto it, at mirrored (y, z) positions.
  auto colourAt = [](const Scene& s, const Eigen::Vector3d& from, const Eigen::Vector3d& dir,
                     Hit& hit) {
    EXPECT_TRUE(s.raycast(from, dir, 1.0, hit));
    return s.surfaceColor(hit.material, hit.uv, 0.004);
  };
  int compared = 0, differing_plain = 0;
  for (double z = 0.2; z < hi.z() - 0.1; z += 0.37) {
    for (double y = lo.y() + 0.1; y < hi.y() - 0.1; y += 0.23) {
      const double y_mirror = 2.0 * cy - y;
      Hit h1, h2, h3;
      const Eigen::Vector3f a =
          colourAt(aliased, {lo.x() + 0.02, y, z}, -Eigen::Vector3d::UnitX(), h1);
      const Eigen::Vector3f b =
          colourAt(aliased, {hi.x() - 0.02, y_mirror, z}, Eigen::Vector3d::UnitX(), h2);
      EXPECT_LT((a - b).cwiseAbs().maxCoeff(), 0.01f) << "y " << y << " z " << z;
      EXPECT_EQ(aliased.material(h1.material).seed, aliased.material(h2.material).seed);
      EXPECT_EQ(aliased.material(h1.material).style, aliased.material(h2.material).style);
      const Eigen::Vector3f c =
          colourAt(plain, {hi.x() - 0.02, y_mirror, z}, Eigen::Vector3d::UnitX(), h3);
      differing_plain += (a - c).cwiseAbs().maxCoeff() > 10.0f;
      ++compared;
    }
  }
  EXPECT_GT(compared, 50);
  EXPECT_GT(differing_plain, compared / 2);
  // Every other surface keeps its material (style and seed): only the +x wall's face changed.
  int changed = 0;
  for (MaterialId m = 0; m < plain.materialCount(); ++m)
    changed += plain.material(m).seed != aliased.material(m).seed;
  EXPECT_EQ(changed, 1);
}

TEST(RenderAliasing, AMirroredAppearanceShowsTheMirrorImageInEveryOrientation) {
  TextureOptions to;
  to.size_log2 = 7;  // small textures: the test is about coordinates
  TextureBank bank(3, to);
  const MaterialAppearance base = bank.resolve({TextureStyle::Tiles, 99});
  const double L = 5.3;  // [m] longer than the texture period (0.51 m here)
  for (int orientation = 0; orientation < 8; ++orientation) {
    MaterialAppearance a = base;
    a.orientation = orientation;
    const MaterialAppearance m = mirroredAppearance(a, L);
    EXPECT_EQ(m.texture, a.texture);
    EXPECT_EQ(m.gain, a.gain);
    EXPECT_EQ(m.orientation, orientation ^ 4);
    int textured = 0;
    for (double u = 0.013; u < L; u += 0.137) {
      for (double v = 0.021; v < 1.0; v += 0.111) {
        const Eigen::Vector3f ca = bank.sample(a, {u, v}, 0.004);
        const Eigen::Vector3f cm = bank.sample(m, {L - u, v}, 0.004);
        EXPECT_LT((ca - cm).cwiseAbs().maxCoeff(), 1e-3f) << orientation << " " << u << " " << v;
        // Not trivially equal: the unmirrored appearance at L - u shows something else.
        textured += (ca - bank.sample(a, {L - u, v}, 0.004)).cwiseAbs().maxCoeff() > 5.0f;
      }
    }
    EXPECT_GT(textured, 100) << orientation;
  }
}

TEST(RenderAliasing, SimOptionsReadTheKeyAndTheSequenceLightsBothWallsAlike) {
  IniReader ini = IniReader::fromText("[sim]\naliased_walls = true\n", "test.ini");
  const SimOptions o = SimOptions::load(ini);
  EXPECT_TRUE(o.scene.aliased_walls);
  IniReader bad = IniReader::fromText("[sim]\naliased_walls = maybe\n", "test.ini");
  EXPECT_THROW(SimOptions::load(bad), ConfigError);
  EXPECT_FALSE(SimOptions{}.scene.aliased_walls);
  SimOptions so;
  so.profile.kind = ProfileKind::Handheld;
  so.profile.duration_s = 8.0;
  so.prefetch_frames = false;
  so.scene.aliased_walls = true;
  EXPECT_NE(so.render.light_dir_world.x(), 0.0);
  const SimulatedSequence seq(so);
  EXPECT_EQ(seq.options().render.light_dir_world.x(), 0.0);
  so.scene.aliased_walls = false;
  const SimulatedSequence plain(so);
  EXPECT_EQ(plain.options().render.light_dir_world.x(), so.render.light_dir_world.x());
}

}  // namespace
}  // namespace rgbdi::sim
