// Occupancy OctoMap: ray casting from the camera (free in front of a surface, occupied at it,
// unknown behind), ray count per frame, and map.bt read back with OctoMap.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "synthetic_frames.h"
#include "testing/fixtures.h"

using namespace rgbdi::mapping;
using rgbdi::mapping::test::planeFrame;

namespace {

enum class Cell { Unknown, Free, Occupied };

Cell cellAt(const octomap::OcTree& tree, double x, double y, double z) {
  const octomap::OcTreeNode* n = tree.search(x, y, z);
  if (n == nullptr) return Cell::Unknown;
  return tree.isNodeOccupied(n) ? Cell::Occupied : Cell::Free;
}

/// A point on the ray through pixel (u, v) at depth z (pixels 320, 250 lie on the stride-2 grid).
Eigen::Vector3d onRay(double z, const Eigen::Isometry3d& T = Eigen::Isometry3d::Identity(),
                      int u = 320, int v = 250) {
  const rgbdi::PinholeCamera cam = rgbdi::mapping::test::makeCamera();
  return T * Eigen::Vector3d((u - cam.cx) / cam.fx * z, (v - cam.cy) / cam.fy * z, z);
}

Cell cellAt(const octomap::OcTree& tree, const Eigen::Vector3d& p) {
  return cellAt(tree, p.x(), p.y(), p.z());
}

}  // namespace

TEST(OccupancyMap, RaysCarveFreeSpaceUpToTheSurfaceAndMarkItOccupied) {
  OccupancyMap map{MappingOptions{}};
  map.insert(planeFrame(2000), Eigen::Isometry3d::Identity());
  // Stride 2 on the 56 x 46 grid: 28 x 23 rays.
  EXPECT_EQ(map.stats().rays, 28u * 23u);
  EXPECT_EQ(map.stats().scans, 1u);
  const octomap::OcTree& t = map.tree();
  EXPECT_EQ(cellAt(t, onRay(2.01)), Cell::Occupied);
  EXPECT_EQ(cellAt(t, onRay(1.0)), Cell::Free);
  EXPECT_EQ(cellAt(t, onRay(0.3)), Cell::Free);
  EXPECT_EQ(cellAt(t, onRay(2.6)), Cell::Unknown);      // behind the surface
  EXPECT_EQ(cellAt(t, 0.01, 3.0, 1.0), Cell::Unknown);  // outside the field of view
  EXPECT_GT(map.leafCount(), 1000u);
  EXPECT_GT(map.memoryBytes(), map.leafCount() * 16);
}

TEST(OccupancyMap, ReadingsBeyondTheMaximumDepthOnlyClearSpace) {
  OccupancyMap map{MappingOptions{}};  // depth_max_m = 6
  map.insert(planeFrame(8000), Eigen::Isometry3d::Identity());
  const octomap::OcTree& t = map.tree();
  EXPECT_EQ(cellAt(t, onRay(5.0)), Cell::Free);
  EXPECT_EQ(cellAt(t, onRay(7.0)), Cell::Unknown);
  EXPECT_EQ(cellAt(t, onRay(8.01)), Cell::Unknown);
  std::size_t occupied = 0;
  for (auto it = t.begin_leafs(); it != t.end_leafs(); ++it) occupied += t.isNodeOccupied(*it);
  EXPECT_EQ(occupied, 0u);
}

TEST(OccupancyMap, PosesMoveTheRays) {
  OccupancyMap map{MappingOptions{}};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // Camera at (5, 0, 1) looking along world +x (optical z -> world x).
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = Eigen::Vector3d(5, 0, 1);
  map.insert(planeFrame(2000), T);
  const octomap::OcTree& t = map.tree();
  EXPECT_NEAR(onRay(2.01, T).x(), 7.01, 1e-12);
  EXPECT_EQ(cellAt(t, onRay(2.01, T)), Cell::Occupied);
  EXPECT_EQ(cellAt(t, onRay(1.0, T)), Cell::Free);
  EXPECT_EQ(cellAt(t, onRay(2.01)), Cell::Unknown);
}

TEST(OccupancyMap, MapBtIsReadBackByOctomapWithTheSameCells) {
  OccupancyMap map{MappingOptions{}};
  map.insert(planeFrame(2000), Eigen::Isometry3d::Identity());
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.3, 0.0, -0.5);
  map.insert(planeFrame(2500), T);
  const std::string path = rgbdi::test::makeTempDir("rgbdi_bt") + "/map.bt";
  // Nothing on the console (OctoMap's own writer prints " done." on stderr: rgbdi-slam printed
  // it once per .bt file after its progress line), and the bytes of OctoMap's own writer.
  testing::internal::CaptureStderr();
  map.write(path);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  std::ostringstream octomap_bytes;
  testing::internal::CaptureStderr();
  ASSERT_TRUE(map.tree().writeBinaryConst(octomap_bytes));
  testing::internal::GetCapturedStderr();
  std::ifstream written(path, std::ios::binary);
  EXPECT_TRUE(std::string(std::istreambuf_iterator<char>(written), {}) == octomap_bytes.str());
  octomap::OcTree read(0.1);
  ASSERT_TRUE(read.readBinary(path));
  EXPECT_DOUBLE_EQ(read.getResolution(), 0.05);
  // Binary files hold the maximum-likelihood state: every leaf keeps its free/occupied class.
  std::size_t leaves = 0;
  for (auto it = map.tree().begin_leafs(); it != map.tree().end_leafs(); ++it) {
    const octomap::OcTreeNode* n = read.search(it.getKey());
    ASSERT_NE(n, nullptr);
    ASSERT_EQ(read.isNodeOccupied(n), map.tree().isNodeOccupied(*it));
    ++leaves;
  }
  EXPECT_GT(leaves, 1000u);
  EXPECT_THROW(map.write("/nonexistent_dir_rgbdi/map.bt"), rgbdi::IoError);
}

TEST(OccupancyMap, RebuildRayCastsTheKeyframesKeptPointsAtTheirPoses) {
  MappingOptions o;
  PointMap points(o);
  KeyframeStore store;
  for (std::uint64_t id = 0; id < 2; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.T_world_cam.translation() = Eigen::Vector3d(0.5 * static_cast<double>(id), 0, 0);
    kf.points = points.insertKeyframe(planeFrame(2000), kf.T_world_cam);
    store.add(kf);
  }
  OccupancyMap rebuilt(o), expected(o);
  rebuilt.insert(planeFrame(3000), Eigen::Isometry3d::Identity());  // discarded by rebuild()
  rebuilt.rebuild(store);
  for (const Keyframe& kf : store.keyframes()) expected.insertPoints(kf.points, kf.T_world_cam);
  EXPECT_EQ(rebuilt.stats().rays, 2 * 644u);  // every 4th of the 2576 kept points (stride 2)
  EXPECT_EQ(rebuilt.leafCount(), expected.leafCount());
  for (auto it = expected.tree().begin_leafs(); it != expected.tree().end_leafs(); ++it) {
    const octomap::OcTreeNode* n = rebuilt.tree().search(it.getKey());
    ASSERT_NE(n, nullptr);
    ASSERT_EQ(n->getLogOdds(), it->getLogOdds());
  }
}

TEST(OccupancyMap, KeptPointsCastEveryStrideSquaredRayAndAllMarkTheirCellsOccupied) {
  MappingOptions every_ray;
  every_ray.occupancy_grid_stride = 1;
  PointMap points(every_ray);
  const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  // A slanted surface, so that neighbouring points end in different cells.
  rgbdi::RgbdFrame f = planeFrame(2000);
  for (int v = 0; v < f.depth.rows; ++v)
    for (int u = 0; u < f.depth.cols; ++u)
      f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(1500 + 2 * u + v);
  const std::vector<MapPoint> kept = points.insertKeyframe(f, T);
  ASSERT_EQ(kept.size(), 2576u);
  OccupancyMap full(every_ray), decimated{MappingOptions{}};  // stride 1 vs the default 2
  full.insertPoints(kept, T);
  decimated.insertPoints(kept, T);
  EXPECT_EQ(full.stats().rays, 2576u);
  EXPECT_EQ(decimated.stats().rays, 644u);
  // The same occupied cells (every point marks its cell); free cells are a subset of the full
  // casting's (47 % of them for this single view: near the camera neighbouring rays cross the
  // same cells, far away they do not; later keyframes carve more).
  std::size_t occupied_full = 0, free_full = 0, free_decimated = 0;
  for (auto it = full.tree().begin_leafs(); it != full.tree().end_leafs(); ++it) {
    const octomap::OcTreeNode* n = decimated.tree().search(it.getKey());
    if (full.tree().isNodeOccupied(*it)) {
      ++occupied_full;
      ASSERT_NE(n, nullptr);
      ASSERT_TRUE(decimated.tree().isNodeOccupied(n));
    } else {
      ++free_full;
      if (n != nullptr) {
        ASSERT_FALSE(decimated.tree().isNodeOccupied(n));
        ++free_decimated;
      }
    }
  }
  std::size_t occupied_decimated = 0, leaves_decimated = 0;
  for (auto it = decimated.tree().begin_leafs(); it != decimated.tree().end_leafs(); ++it) {
    ++leaves_decimated;
    occupied_decimated += decimated.tree().isNodeOccupied(*it);
  }
  EXPECT_EQ(occupied_decimated, occupied_full);
  EXPECT_EQ(leaves_decimated, occupied_decimated + free_decimated);  // nothing outside the full map
  EXPECT_GT(occupied_full, 100u);
  EXPECT_GT(free_decimated * 5, free_full * 2);
  // A point that casts no ray still marks its cell: the second kept point.
  const Eigen::Vector3d second = kept[1].p_cam.cast<double>();
  EXPECT_EQ(cellAt(decimated.tree(), second), Cell::Occupied);
}

TEST(OccupancyMap, UpdatesInOctreeOrderGiveOctomapsOwnInsertionResult) {
  // castRays updates the cells sorted by Morton code instead of in the hash set's order; every
  // cell is updated once per scan, so the tree must be exactly OctoMap's insertPointCloud result.
  MappingOptions every_ray;
  every_ray.occupancy_grid_stride = 1;
  PointMap points(every_ray);
  rgbdi::RgbdFrame f = planeFrame(2000);
  for (int v = 0; v < f.depth.rows; ++v)
    for (int u = 0; u < f.depth.cols; ++u)
      f.depth.at<std::uint16_t>(v, u) = static_cast<std::uint16_t>(1500 + 3 * u + 2 * v);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).matrix();
  T.translation() = Eigen::Vector3d(0.31, -0.17, 0.05);
  const std::vector<MapPoint> kept = points.insertKeyframe(f, T);
  ASSERT_EQ(kept.size(), 2576u);
  OccupancyMap ours(every_ray);
  ours.insertPoints(kept, T);

  octomap::OcTree reference(every_ray.occupancy_resolution_m);
  reference.setProbHit(every_ray.occupancy_prob_hit);
  reference.setProbMiss(every_ray.occupancy_prob_miss);
  octomap::Pointcloud cloud;
  for (const MapPoint& p : kept) {
    const Eigen::Vector3d w = T * p.p_cam.cast<double>();
    cloud.push_back(static_cast<float>(w.x()), static_cast<float>(w.y()),
                    static_cast<float>(w.z()));
  }
  const Eigen::Vector3d o = T.translation();
  reference.insertPointCloud(cloud,
                             octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                              static_cast<float>(o.z())),
                             every_ray.depth_max_m, /*lazy_eval=*/true, /*discretize=*/true);
  reference.updateInnerOccupancy();

  ASSERT_EQ(ours.leafCount(), reference.getNumLeafNodes());
  ASSERT_GT(ours.leafCount(), 1000u);
  for (auto it = reference.begin_leafs(); it != reference.end_leafs(); ++it) {
    const octomap::OcTreeNode* n = ours.tree().search(it.getKey());
    ASSERT_NE(n, nullptr);
    ASSERT_EQ(n->getLogOdds(), it->getLogOdds());
  }
  std::ostringstream ours_bytes, reference_bytes;
  ASSERT_TRUE(ours.tree().write(ours_bytes));
  ASSERT_TRUE(reference.write(reference_bytes));
  EXPECT_EQ(ours_bytes.str(), reference_bytes.str());
}
