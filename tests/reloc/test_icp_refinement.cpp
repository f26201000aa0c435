// The optional parts of the ICP refinement (GeometricRelocaliser::refine, RefineExtras) and the
// map's view directions (PointIndex): known answers on synthetic surfaces.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/reloc/geometric_relocaliser.h"
#include "rgbdi/reloc/point_index.h"

using namespace rgbdi::reloc;

namespace {
Eigen::Isometry3d yawPose(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}
/// A corner of a room: walls x = 0 (along y) and y = 0 (along x), 0.5 m high, and a 1.5 x 1.5 m
/// floor, on a lattice with no two points in one 1e-4 m voxel.
std::vector<Eigen::Vector3d> roomCorner() {
  std::vector<Eigen::Vector3d> p;
  for (int i = 0; i < 60; ++i)
    for (int k = 0; k < 10; ++k) {
      p.emplace_back(0.025 * i + 0.01, 0.0, 0.05 * k + 0.01);
      p.emplace_back(0.0, 0.025 * i + 0.01, 0.05 * k + 0.01);
    }
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) p.emplace_back(0.05 * i + 0.02, 0.05 * j + 0.02, 0.0);
  return p;
}
}  // namespace

TEST(IcpRefinement, NormalsFaceTheCamerasThatSawThem) {
  // A floor seen from above and a ceiling seen from below: their normals point to the cameras.
  std::vector<Eigen::Vector3d> points, views;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) {
      points.emplace_back(0.02 * i, 0.02 * j, 0.0);
      views.emplace_back(0.0, 0.0, 1.0);
      points.emplace_back(0.02 * i, 0.02 * j, 2.0);
      views.emplace_back(0.0, 0.0, -1.0);
    }
  const PointIndex index(points, views, 1e-4, 0.1);
  ASSERT_EQ(index.points().size(), 200u);
  ASSERT_EQ(index.views().size(), 200u);
  for (std::size_t i = 0; i < index.points().size(); ++i) {
    const double up = index.points()[i].z() < 1.0 ? 1.0 : -1.0;
    EXPECT_NEAR(index.normals()[i].z(), up, 1e-12) << i;
    EXPECT_NEAR(index.views()[i].z(), up, 1e-12) << i;
  }
}

TEST(IcpRefinement, ThinningAveragesTheDirectionsPerVoxel) {
  // Two samples in one 0.1 m voxel seen from x and from y: one point, the unit mean direction.
  std::vector<Eigen::Vector3d> dirs;
  const std::vector<Eigen::Vector3d> thin =
      PointIndex::thinDirections({{0.01, 0.01, 0.01}, {0.03, 0.05, 0.01}, {0.5, 0.5, 0.5}},
                                 {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, -1.0}}, 0.1, &dirs);
  ASSERT_EQ(thin.size(), 2u);
  EXPECT_NEAR((thin[0] - Eigen::Vector3d(0.02, 0.03, 0.01)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((dirs[0] - Eigen::Vector3d(1.0, 1.0, 0.0) / std::sqrt(2.0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((dirs[1] - Eigen::Vector3d(0.0, 0.0, -1.0)).norm(), 0.0, 1e-15);
}

TEST(IcpRefinement, TheBackOfAPanelIsNotPairedWithItsFront) {
  // The map saw a 4 cm panel (x = 0) from -x; the run sees its back (x = 0.04) from +x. Without
  // the side test every back sample pairs with the front 4 cm away; with it, none does and
  // they leave the judged samples.
  std::vector<Eigen::Vector3d> map_points, map_views, local, local_views;
  for (int i = 0; i < 20; ++i)
    for (int k = 0; k < 10; ++k) {
      map_points.emplace_back(0.0, 0.025 * i, 0.05 * k);
      map_views.emplace_back(-1.0, 0.0, 0.0);
      local.emplace_back(0.04, 0.025 * i, 0.05 * k);
      local_views.emplace_back(1.0, 0.0, 0.0);
    }
  const PointIndex index(map_points, map_views, 1e-4, 0.15);
  const GeometricRelocaliser::Refinement all =
      GeometricRelocaliser::refine(local, index, Eigen::Isometry3d::Identity(), 0.15, 1, 1e9);
  EXPECT_EQ(all.pairs, 200);
  EXPECT_EQ(all.other_side, 0);
  EXPECT_NEAR(all.rms_m, 0.04, 1e-12);
  RefineExtras sides;
  sides.local_views = local_views;
  sides.min_view_cos = 0.0;
  const GeometricRelocaliser::Refinement same = GeometricRelocaliser::refine(
      local, index, Eigen::Isometry3d::Identity(), 0.15, 1, 1e9, {}, 0.0, true, sides);
  EXPECT_EQ(same.pairs, 0);
  EXPECT_EQ(same.other_side, 200);
  // Seen from the map's side (turned by the yaw of T: here a half turn), every sample pairs.
  sides.local_views.assign(local.size(), Eigen::Vector3d(1.0, 0.0, 0.0));
  std::vector<Eigen::Vector3d> turned;
  for (const Eigen::Vector3d& p : map_points)
    turned.push_back(yawPose(M_PI, Eigen::Vector3d::Zero()).inverse() * p);
  const GeometricRelocaliser::Refinement front = GeometricRelocaliser::refine(
      turned, index, yawPose(M_PI, Eigen::Vector3d::Zero()), 0.15, 1, 1e9, {}, 0.0, true, sides);
  EXPECT_EQ(front.pairs, 200);
  EXPECT_EQ(front.other_side, 0);
}

TEST(IcpRefinement, TheTiltOfTheSubmapIsSolvedAndTheAnchorPlaced) {
  // The local copy of a room corner is tilted by 1.5 deg about a horizontal axis through the
  // anchor, then moved by a yaw of 2 deg and (4, -3, 2) cm. With the tilt solved, the anchor
  // lands exactly where it belongs and the yaw is exact; without, the fit is off.
  const std::vector<Eigen::Vector3d> map_points = roomCorner();
  const Eigen::Vector3d anchor_map(0.7, 0.6, 0.3);
  const Eigen::Matrix3d tilt =
      Eigen::AngleAxisd(1.5 * M_PI / 180.0, Eigen::Vector3d(0.6, 0.8, 0.0)).toRotationMatrix();
  const Eigen::Isometry3d motion = yawPose(2.0 * M_PI / 180.0, Eigen::Vector3d(0.04, -0.03, 0.02));
  // map = motion (a + tilt (local_in_level - a)): the local points are its inverse.
  std::vector<Eigen::Vector3d> local;
  const Eigen::Vector3d anchor_part = motion.inverse() * anchor_map;
  for (const Eigen::Vector3d& p : map_points)
    local.push_back(anchor_part + tilt.transpose() * (motion.inverse() * p - anchor_part));
  const PointIndex index(map_points, 1e-4, 0.15);
  RefineExtras extras;
  extras.tilt_sigma_rad = 1.0;  // a weak prior: weighs (huber / sigma)^2 = 1e-4 pairs
  extras.anchor_part = anchor_part;
  // T0 = the motion's yaw and translation: the tilt about the anchor is what is left.
  const GeometricRelocaliser::Refinement r =
      GeometricRelocaliser::refine(local, index, motion, 0.15, 50, 0.01, {}, 0.0, true, extras);
  EXPECT_LT(r.rms_m, 1e-4);
  EXPECT_NEAR(r.tilt_rad, 1.5 * M_PI / 180.0, 2e-5);
  EXPECT_NEAR((r.T * anchor_part - anchor_map).norm(), 0.0, 1e-4);
  const Eigen::Matrix3d E = r.T.linear().transpose() * motion.linear();
  EXPECT_NEAR(std::atan2(E(1, 0), E(0, 0)), 0.0, 5e-4);  // a tilt turns the yaw to second order
  EXPECT_NEAR(r.T.linear()(2, 2), 1.0, 1e-15);           // the result stays yaw + translation
  // Without the tilt the same start cannot fit the surfaces.
  const GeometricRelocaliser::Refinement plain =
      GeometricRelocaliser::refine(local, index, motion, 0.15, 50, 0.01);
  EXPECT_GT(plain.rms_m, 1e-3);
  EXPECT_DOUBLE_EQ(plain.tilt_rad, 0.0);
}
