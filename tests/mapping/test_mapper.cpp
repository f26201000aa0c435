// Mapper: the mapping stage composition (point octree, occupancy, keyframe store, viewpoint
// culling) and the map correction after a pose-graph solve.
#include <gtest/gtest.h>

#include <sstream>

#include "mapping/synthetic_frames.h"
#include "rgbdi/mapping/mapper.h"

using namespace rgbdi;
using namespace rgbdi::mapping;

namespace {
Keyframe keyframeAt(std::uint64_t id, const Eigen::Vector3d& p) {
  Keyframe k;
  k.id = id;
  k.frame_index = id;
  k.t = static_cast<double>(id);
  k.T_world_cam.translation() = p;
  return k;
}
}  // namespace

TEST(Mapper, AKeyframeFromAMappedViewpointAddsNoPointsButIsStored) {
  MappingOptions o;
  Mapper m(o, true);
  const RgbdFrame f = test::planeFrame(2000);
  m.addKeyframe(keyframeAt(0, Eigen::Vector3d::Zero()), f);
  const std::size_t points = m.pointMap().pointCount();
  EXPECT_GT(points, 1000u);
  m.addKeyframe(keyframeAt(1, Eigen::Vector3d(0.05, 0, 0)), f);  // within 0.15 m, same view
  EXPECT_EQ(m.pointMap().pointCount(), points);
  EXPECT_EQ(m.store().size(), 2u);
  EXPECT_TRUE(m.store().get(1).points.empty());
  EXPECT_EQ(m.stats().keyframes_adding_points, 1u);
  ASSERT_EQ(m.insertions().size(), 2u);
  EXPECT_EQ(m.insertions()[0].id, 0u);
  EXPECT_EQ(m.insertions()[0].points, points);
  EXPECT_EQ(m.insertions()[1].points, 0u);
  EXPECT_DOUBLE_EQ(m.insertions()[1].t, 1.0);
  EXPECT_THROW(m.addKeyframe(keyframeAt(1, Eigen::Vector3d::Zero()), f), std::invalid_argument);
  ASSERT_NE(m.occupancy(), nullptr);
  EXPECT_EQ(m.occupancy()->leafCount(), 0u);  // cast by finish()
  m.finish();
  EXPECT_GT(m.occupancy()->leafCount(), 0u);
}

TEST(Mapper, CorrectionMovesTheKeyframesPointsWithTheirPose) {
  MappingOptions o;
  Mapper m(o, false);
  EXPECT_EQ(m.occupancy(), nullptr);
  // At 0.5 m the 10 px sampling grid puts 4 points into every 2 cm leaf (>= 3: kept by rebuilds).
  const RgbdFrame f = test::planeFrame(500);
  m.addKeyframe(keyframeAt(0, Eigen::Vector3d::Zero()), f);
  auto centroid = [&] {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& wp : m.pointMap().points()) c += wp.p_world.cast<double>();
    return Eigen::Vector3d(c / static_cast<double>(m.pointMap().pointCount()));
  };
  const Eigen::Vector3d c0 = centroid();
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(1.0, -0.5, 0.25);
  const MapCorrection c = m.correct({{0, moved}, {42, moved}});  // 42: not in the map, ignored
  EXPECT_EQ(c.keyframes_moved, 1u);
  EXPECT_EQ(m.stats().corrections, 1u);
  ASSERT_GT(m.pointMap().pointCount(), 0u);
  // Moved by whole leaves in x and y, so only the leaves cut by the half-leaf z shift can fall
  // below min_points_per_leaf_rebuild.
  EXPECT_GT(c.rebuild.kept_points, c.rebuild.input_points / 2);
  EXPECT_EQ(c.rebuild.keyframes, 1u);
  // The plane moved with the keyframe (a few border leaves may have been dropped).
  EXPECT_LT((centroid() - (c0 + moved.translation())).norm(), 0.01);
  EXPECT_TRUE(m.store().get(0).T_world_cam.isApprox(moved));
  // The same poses again: nothing moved, no rebuild.
  EXPECT_EQ(m.correct({{0, moved}}).keyframes_moved, 0u);
  EXPECT_EQ(m.stats().corrections, 1u);
}

TEST(Mapper, AfterACorrectionTheViewpointsFollowTheCorrectedPoses) {
  MappingOptions o;
  Mapper m(o, false);
  const RgbdFrame f = test::planeFrame(2000);
  m.addKeyframe(keyframeAt(0, Eigen::Vector3d::Zero()), f);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(3.0, 0, 0);
  m.correct({{0, moved}});
  const std::size_t before = m.pointMap().pointCount();
  // Near the corrected viewpoint: covered, adds nothing; near the old one: new, adds points.
  m.addKeyframe(keyframeAt(1, Eigen::Vector3d(3.05, 0, 0)), f);
  EXPECT_EQ(m.pointMap().pointCount(), before);
  m.addKeyframe(keyframeAt(2, Eigen::Vector3d(0.0, 0, 0)), f);
  EXPECT_GT(m.pointMap().pointCount(), before);
}

TEST(Mapper, FinishCastsTheOccupancyMapOnceFromTheFinalPoses) {
  MappingOptions o;
  Mapper m(o, true);
  const RgbdFrame f = test::planeFrame(2000);
  m.addKeyframe(keyframeAt(0, Eigen::Vector3d::Zero()), f);
  m.addKeyframe(keyframeAt(1, Eigen::Vector3d(1.0, 0, 0)), f);
  ASSERT_EQ(m.stats().keyframes_adding_points, 2u);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(0, 0, 1.0);
  m.correct({{0, moved}});
  EXPECT_EQ(m.occupancy()->leafCount(), 0u);  // nothing cast before finish()
  EXPECT_EQ(m.stats().occupancy_rebuild_ms, 0.0);
  m.finish();
  EXPECT_GT(m.stats().occupancy_rebuild_ms, 0.0);
  EXPECT_EQ(m.occupancy()->stats().scans, 2u);  // each keyframe cast once

  // The same as casting the keyframes directly at their final poses, in insertion order.
  OccupancyMap direct(o);
  direct.insertPoints(m.store().get(0).points, moved);
  direct.insertPoints(m.store().get(1).points, m.store().get(1).T_world_cam);
  std::ostringstream ours, expected;
  ASSERT_TRUE(m.occupancy()->tree().write(ours));
  ASSERT_TRUE(direct.tree().write(expected));
  EXPECT_EQ(ours.str(), expected.str());

  // Nothing new: finish() casts nothing again; a new keyframe makes it cast everything again.
  m.finish();
  EXPECT_EQ(m.occupancy()->stats().scans, 2u);
  m.addKeyframe(keyframeAt(2, Eigen::Vector3d(-1.0, 0, 0)), f);
  m.finish();
  EXPECT_EQ(m.occupancy()->stats().scans, 3u);
}
