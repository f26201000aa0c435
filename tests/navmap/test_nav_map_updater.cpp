// NavMapUpdater: the incremental build equals the full build (buildNavMap) from the same points
// on the same path, layer by layer and bit for bit, however the points are split into keyframes
// and while the path grows; clear() forgets the points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/navmap/nav_map_updater.h"

using namespace rgbdi::navmap;

namespace {

/// A room seen with 1 cm height noise around a path along x from -4 m to 4 m (over several
/// 64-cell tiles, negative coordinates too): floor, a 20 cm step up, a 30 cm deep hole, a ramp
/// of 15 deg, a box, a table top 0.75 m high, a wall, a hole's wall seen only 8 cm down (drop
/// faces, NavMapOptions::drop_face_min_rise_m), and points exactly on cell edges.
std::vector<Eigen::Vector3f> scene(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> ux(-5.0f, 5.0f), uy(-2.0f, 2.0f), unit(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  std::vector<Eigen::Vector3f> p;
  for (int k = 0; k < 60000; ++k) {
    const float x = ux(rng), y = uy(rng);
    float z = 0.0f;
    if (x > 2.0f && y > 0.8f) z = 0.2f;                              // step up
    if (x > -3.0f && x < -2.5f && y < -1.0f) z = -0.3f;              // hole
    if (x > 0.5f && x < 1.5f && y < -0.8f) z = (x - 0.5f) * 0.268f;  // ramp
    p.emplace_back(x, y, z + noise(rng));
  }
  for (int k = 0; k < 4000; ++k) {  // a box 0.4 m high
    p.emplace_back(-1.0f + 0.3f * unit(rng), 1.0f + 0.3f * unit(rng), 0.4f * unit(rng));
    // a table top, above the clearance band
    p.emplace_back(3.0f + 0.8f * unit(rng), -1.5f + 0.5f * unit(rng), 0.75f + noise(rng));
    // a wall at y = 2
    p.emplace_back(ux(rng), 2.0f + 0.02f * unit(rng), 2.0f * unit(rng));
  }
  for (int k = 0; k < 400; ++k)  // a wall going down from the floor at x = -2, seen 8 cm down
    p.emplace_back(-2.0f + 0.02f * unit(rng), 0.5f + 0.5f * unit(rng), -0.08f * unit(rng));
  for (int k = -20; k <= 20; ++k)  // on cell edges, where binning is the most fragile
    for (int j = 0; j < 3; ++j) p.emplace_back(0.05f * k, 0.05f * j, 0.001f * j);
  return p;
}

std::vector<Eigen::Vector3d> path(std::size_t poses) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t k = 0; k < poses; ++k)
    out.emplace_back(-4.0 + 0.05 * static_cast<double>(k), 0.1 * std::sin(0.1 * k), 0.3);
  return out;
}

/// Bitwise equal (NaN equals NaN of the same bits).
template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expectSame(const NavMap& inc, const NavMap& full) {
  EXPECT_EQ(inc.grid.width, full.grid.width);
  EXPECT_EQ(inc.grid.height, full.grid.height);
  EXPECT_EQ(inc.grid.origin_x_m, full.grid.origin_x_m);
  EXPECT_EQ(inc.grid.origin_y_m, full.grid.origin_y_m);
  EXPECT_TRUE(sameBits(inc.ground_z_m, full.ground_z_m));
  EXPECT_TRUE(sameBits(inc.ground_sigma_m, full.ground_sigma_m));
  EXPECT_TRUE(sameBits(inc.slope_deg, full.slope_deg));
  EXPECT_TRUE(sameBits(inc.step_m, full.step_m));
  EXPECT_TRUE(sameBits(inc.roughness_m, full.roughness_m));
  EXPECT_TRUE(sameBits(inc.traversability, full.traversability));
  EXPECT_TRUE(sameBits(inc.state, full.state));
  EXPECT_TRUE(sameBits(inc.driven, full.driven));
  EXPECT_EQ(std::memcmp(&inc.path_height_m, &full.path_height_m, sizeof(double)), 0);
}

}  // namespace

TEST(NavMapUpdater, KeyframeByKeyframeEqualsTheFullBuildWhileThePathGrows) {
  std::vector<Eigen::Vector3f> all = scene(3);
  std::shuffle(all.begin(), all.end(), std::mt19937(5));
  const std::vector<Eigen::Vector3d> full_path = path(161);
  const NavMapOptions o;
  NavMapUpdater up(o);
  std::vector<Eigen::Vector3f> so_far;
  const std::size_t keyframes = 8, per = all.size() / keyframes + 1;
  for (std::size_t k = 0; k < keyframes; ++k) {
    const std::vector<Eigen::Vector3f> kf(
        all.begin() + static_cast<std::ptrdiff_t>(std::min(all.size(), k * per)),
        all.begin() + static_cast<std::ptrdiff_t>(std::min(all.size(), (k + 1) * per)));
    up.addPoints(kf);
    so_far.insert(so_far.end(), kf.begin(), kf.end());
    const std::vector<Eigen::Vector3d> p(full_path.begin(),
                                         full_path.begin() + 20 * static_cast<int>(k + 1) + 1);
    SCOPED_TRACE(k);
    const NavMap inc = up.build(p);
    const NavMap full = buildNavMap(so_far, p, o);
    expectSame(inc, full);
  }
  EXPECT_EQ(up.pointCount(), all.size());
  // The final map has every kind of cell: the scene is not trivially equal.
  const NavMap m = up.build(full_path);
  for (CellState s : {CellState::kFree, CellState::kObstacle, CellState::kStepEdge,
                      CellState::kUnknown, CellState::kLowered})
    EXPECT_GT(m.count(s), 0u) << toString(s);
  // ... drop faces among the step edges.
  NavMapOptions no_drops;
  no_drops.drop_face_min_rise_m = 0.0;
  EXPECT_GT(m.count(CellState::kStepEdge),
            buildNavMap(all, full_path, no_drops).count(CellState::kStepEdge) + 5);
}

TEST(NavMapUpdater, IgnoresNonFinitePointsAsTheFullBuildDoes) {
  std::vector<Eigen::Vector3f> pts = scene(4);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  pts.emplace_back(nan, 0.0f, 0.0f);
  pts.emplace_back(0.0f, inf, 0.0f);
  pts.emplace_back(0.1f, 0.1f, nan);
  pts.emplace_back(1e30f, 0.0f, 0.0f);
  NavMapUpdater up(NavMapOptions{});
  up.addPoints(pts);
  EXPECT_EQ(up.pointCount(), pts.size() - 4);
  expectSame(up.build(path(161)), buildNavMap(pts, path(161), NavMapOptions{}));
}

TEST(NavMapUpdater, ClearForgetsThePoints) {
  const NavMapOptions o;
  NavMapUpdater up(o);
  up.addPoints(scene(6));
  up.build(path(161));  // its layers must not leak into the next build
  up.clear();
  EXPECT_EQ(up.pointCount(), 0u);
  EXPECT_EQ(up.occupiedCells(), 0u);
  const std::vector<Eigen::Vector3f> other = scene(7);
  up.addPoints(other);
  expectSame(up.build(path(161)), buildNavMap(other, path(161), o));
  EXPECT_THROW(up.build({}), std::invalid_argument);
}

TEST(NavMapUpdater, ABuildAfterThePathMovedOrShrankEqualsTheFullBuild) {
  // A loop correction moves the path (and the grid with it); a shorter path shrinks the grid.
  const std::vector<Eigen::Vector3f> pts = scene(8);
  const NavMapOptions o;
  NavMapUpdater up(o);
  up.addPoints(pts);
  std::vector<Eigen::Vector3d> p = path(161);
  expectSame(up.build(p), buildNavMap(pts, p, o));
  for (Eigen::Vector3d& q : p) q += Eigen::Vector3d(0.37, -0.21, 0.02);
  expectSame(up.build(p), buildNavMap(pts, p, o));
  p.resize(60);
  expectSame(up.build(p), buildNavMap(pts, p, o));
}
