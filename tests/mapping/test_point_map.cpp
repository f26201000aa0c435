// The octree point mapper: grid subsampling, leaf capacity, rebuild after pose updates, memory
// bound. Expectations are exact: analytic plane geometry and an independent voxel-counting
// reference of the paper's rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <tuple>
#include <vector>

#include "rgbdi/mapping/point_map.h"
#include "synthetic_frames.h"

using namespace rgbdi::mapping;
using rgbdi::PinholeCamera;
using rgbdi::RgbdFrame;
using rgbdi::mapping::test::makeCamera;
using rgbdi::mapping::test::pixelColour;
using rgbdi::mapping::test::planeFrame;

namespace {

constexpr std::size_t kGridCols = 56;  // u = 40, 50, ..., 590
constexpr std::size_t kGridRows = 46;  // v = 10, 20, ..., 460
constexpr std::size_t kGridPoints = kGridCols * kGridRows;

Eigen::Isometry3d translation(double x, double y, double z) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

Eigen::Isometry3d randomPose(std::mt19937_64& rng, double trans, double rot_rad) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  T.linear() = Eigen::AngleAxisd(rot_rad * u(rng), axis).toRotationMatrix();
  T.translation() = trans * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

/// Independent statement of the paper's rules: voxel = floor(coordinate / resolution) (OctoMap's
/// key), a voxel accepts points until it holds `capacity`; a rebuild re-inserts the keyframes'
/// kept points in order and removes voxels holding fewer than `min_count`.
class ReferenceMap {
 public:
  ReferenceMap(double resolution, int capacity) : factor_(1.0 / resolution), capacity_(capacity) {}
  using Voxel = std::tuple<long, long, long>;
  Voxel voxel(const Eigen::Vector3d& p) const {
    return {static_cast<long>(std::floor(p.x() * factor_)),
            static_cast<long>(std::floor(p.y() * factor_)),
            static_cast<long>(std::floor(p.z() * factor_))};
  }
  bool insert(const Eigen::Vector3d& p) {
    int& n = counts_[voxel(p)];
    if (n >= capacity_) return false;
    ++n;
    return true;
  }
  int count(const Eigen::Vector3d& p) const {
    const auto it = counts_.find(voxel(p));
    return it == counts_.end() ? 0 : it->second;
  }
  /// Points in the 3 x 3 x 3 cells of two voxels around p's cell (PointMap's isolation rule).
  int neighbourhoodCount(const Eigen::Vector3d& p) const {
    auto half = [](long v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); };  // floor(v / 2)
    if (cells_.empty())
      for (const auto& [v, c] : counts_) {
        const auto [vx, vy, vz] = v;
        cells_[{half(vx), half(vy), half(vz)}] += c;
      }
    const auto [x, y, z] = voxel(p);
    int n = 0;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({half(x) + dx, half(y) + dy, half(z) + dz});
          if (it != cells_.end()) n += it->second;
        }
    return n;
  }
  std::size_t voxels() const { return counts_.size(); }
  void clear() { counts_.clear(); }

 private:
  double factor_;
  int capacity_;
  std::map<Voxel, int> counts_;
  mutable std::map<Voxel, int> cells_;  ///< counts per cell of two voxels (built on first use)
};

std::vector<MapPoint> randomCloud(std::mt19937_64& rng, std::size_t n, double half_size) {
  std::uniform_real_distribution<float> u(static_cast<float>(-half_size),
                                          static_cast<float>(half_size));
  std::uniform_int_distribution<int> c(0, 255);
  std::vector<MapPoint> pts(n);
  for (MapPoint& p : pts) {
    p.p_cam = Eigen::Vector3f(u(rng), u(rng), 2.0f + u(rng));
    p.rgb = {static_cast<std::uint8_t>(c(rng)), static_cast<std::uint8_t>(c(rng)),
             static_cast<std::uint8_t>(c(rng))};
  }
  return pts;
}

bool samePoint(const MapPoint& a, const MapPoint& b) {
  return a.p_cam == b.p_cam && a.rgb == b.rgb;
}

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PointMap, PlaneGridPointsAreBackProjectedExactly) {
  const PinholeCamera cam = makeCamera();
  PointMap map{MappingOptions{}};
  const std::vector<MapPoint> kept =
      map.insertKeyframe(planeFrame(2000, cam), Eigen::Isometry3d::Identity());
  ASSERT_EQ(kept.size(), kGridPoints);
  EXPECT_EQ(map.stats().grid_points, kGridPoints);
  EXPECT_EQ(map.stats().candidates, kGridPoints);
  EXPECT_EQ(map.stats().accepted, kGridPoints);
  // Points 4 cm apart on a plane: one per 2 cm leaf.
  EXPECT_EQ(map.leafCount(), kGridPoints);
  EXPECT_EQ(map.pointCount(), kGridPoints);
  // Row-major grid order, pinhole back-projection, colour of the sampled pixel.
  for (std::size_t r = 0; r < kGridRows; ++r)
    for (std::size_t c = 0; c < kGridCols; ++c) {
      const int u = 40 + 10 * static_cast<int>(c), v = 10 + 10 * static_cast<int>(r);
      const MapPoint& p = kept[r * kGridCols + c];
      EXPECT_NEAR(p.p_cam.x(), (u - cam.cx) / cam.fx * 2.0, 1e-6);
      EXPECT_NEAR(p.p_cam.y(), (v - cam.cy) / cam.fy * 2.0, 1e-6);
      EXPECT_FLOAT_EQ(p.p_cam.z(), 2.0f);
      const cv::Vec3b expected = pixelColour(u, v);
      EXPECT_EQ(p.rgb, (Rgb{expected[0], expected[1], expected[2]}));
    }
  // World points are the camera points moved by the pose.
  const Eigen::Isometry3d T = translation(1.0, -2.0, 0.5);
  PointMap moved{MappingOptions{}};
  const std::vector<MapPoint> kept2 = moved.insertKeyframe(planeFrame(2000, cam), T);
  ASSERT_EQ(kept2.size(), kGridPoints);
  for (std::size_t i = 0; i < kGridPoints; ++i)
    EXPECT_TRUE(moved.points()[i].p_world.isApprox(
        (T * kept2[i].p_cam.cast<double>()).cast<float>(), 1e-6f));
}

TEST(PointMap, DepthOutsideTheRangeAndHolesAreNotMapped) {
  RgbdFrame f = planeFrame(2000);
  // Four grid pixels with special depths (range is exclusive: (0.3, 6) m).
  f.depth.at<std::uint16_t>(10, 40) = 0;     // hole
  f.depth.at<std::uint16_t>(10, 50) = 299;   // too near
  f.depth.at<std::uint16_t>(10, 60) = 6001;  // too far
  f.depth.at<std::uint16_t>(10, 70) = 301;   // kept
  f.depth.at<std::uint16_t>(20, 40) = 5999;  // kept
  f.depth.at<std::uint16_t>(15, 45) = 0;     // off the grid: irrelevant
  PointMap map{MappingOptions{}};
  const std::vector<MapPoint> kept = map.insertKeyframe(f, Eigen::Isometry3d::Identity());
  EXPECT_EQ(map.stats().grid_points, kGridPoints);
  EXPECT_EQ(map.stats().no_depth, 1u);
  EXPECT_EQ(map.stats().out_of_range, 2u);
  EXPECT_EQ(kept.size(), kGridPoints - 3);
  EXPECT_FLOAT_EQ(kept[0].p_cam.z(), 0.301f);              // (70, 10) is the first kept grid pixel
  EXPECT_FLOAT_EQ(kept[kGridCols - 3].p_cam.z(), 5.999f);  // first pixel of the second row
}

TEST(PointMap, FullLeavesRejectLaterPointsWhichTheKeyframeDoesNotKeep) {
  PointMap map{MappingOptions{}};
  const RgbdFrame f = planeFrame(2000);
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(map.insertKeyframe(f, Eigen::Isometry3d::Identity()).size(), kGridPoints) << k;
  EXPECT_EQ(map.pointCount(), 5 * kGridPoints);
  // Grid points are at x, y = (u - 319.5) * 4 mm: the leaf [20, 40) mm holds none of them.
  EXPECT_EQ(map.pointsInLeafAt(Eigen::Vector3d(0.021, 0.021, 2.0)), 0u);
  EXPECT_EQ(map.pointsInLeafAt(map.points().front().p_world.cast<double>()), 5u);
  // The sixth identical keyframe falls entirely into full leaves.
  EXPECT_TRUE(map.insertKeyframe(f, Eigen::Isometry3d::Identity()).empty());
  EXPECT_EQ(map.stats().rejected_full_leaf, kGridPoints);
  EXPECT_EQ(map.pointCount(), 5 * kGridPoints);
  EXPECT_EQ(map.leafCount(), kGridPoints);
}

TEST(PointMap, CapacityMatchesAnIndependentVoxelCountForRandomClouds) {
  std::mt19937_64 rng(42);
  for (int capacity : {1, 3, 5}) {
    MappingOptions o;
    o.max_points_per_leaf = capacity;
    o.min_points_per_leaf_rebuild = 0;
    PointMap map(o);
    ReferenceMap ref(o.octree_resolution_m, capacity);
    std::size_t expected_total = 0;
    for (int k = 0; k < 20; ++k) {
      const Eigen::Isometry3d T = randomPose(rng, 0.05, 0.05);
      const std::vector<MapPoint> cloud = randomCloud(rng, 3000, 0.1);  // dense: many collisions
      std::vector<MapPoint> expected;
      for (const MapPoint& p : cloud)
        if (ref.insert(T * p.p_cam.cast<double>())) expected.push_back(p);
      const std::vector<MapPoint> kept = map.insertPoints(cloud, T);
      ASSERT_EQ(kept.size(), expected.size()) << "capacity " << capacity << " keyframe " << k;
      for (std::size_t i = 0; i < kept.size(); ++i) ASSERT_TRUE(samePoint(kept[i], expected[i]));
      expected_total += expected.size();
    }
    EXPECT_EQ(map.pointCount(), expected_total);
    EXPECT_EQ(map.leafCount(), ref.voxels());
    EXPECT_LE(map.pointCount(), map.leafCount() * static_cast<std::size_t>(capacity));
    // Every point lies in the leaf the reference assigns it, whose count agrees.
    for (const WorldPoint& p : map.points())
      ASSERT_EQ(map.pointsInLeafAt(p.p_world.cast<double>()),
                static_cast<std::size_t>(ref.count(p.p_world.cast<double>())));
  }
}

TEST(PointMap, RebuildDropsIsolatedLeavesFromTheMapAndTheKeyframes) {
  // Three keyframes see the same plane; a fourth adds two isolated points (one far away, one
  // 8 cm = 4 leaves off the plane): after the rebuild only those two are gone.
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  const RgbdFrame f = planeFrame(2000);
  for (std::uint64_t id = 0; id < 3; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.points = map.insertKeyframe(f, kf.T_world_cam);
    store.add(kf);
  }
  const Eigen::Vector3d on_plane = map.points().front().p_world.cast<double>();
  Keyframe stray;
  stray.id = 3;
  MapPoint far, off;
  far.p_cam = Eigen::Vector3f(10.0f, 0.0f, 0.0f);
  off.p_cam = (on_plane + Eigen::Vector3d(0, 0, -0.08)).cast<float>();
  stray.points = map.insertPoints({far, off}, stray.T_world_cam);
  ASSERT_EQ(stray.points.size(), 2u);
  store.add(stray);
  EXPECT_EQ(map.pointCount(), 3 * kGridPoints + 2);
  EXPECT_FALSE(map.isOutdated(store));
  const RebuildReport r = map.rebuild(store);
  EXPECT_EQ(r.keyframes, 4u);
  EXPECT_EQ(r.input_points, 3 * kGridPoints + 2);
  EXPECT_EQ(r.rejected_full_leaf, 0u);
  EXPECT_EQ(r.sparse_leaves_removed, 2u);
  EXPECT_EQ(r.sparse_points_removed, 2u);
  EXPECT_EQ(r.kept_points, 3 * kGridPoints);
  EXPECT_EQ(map.pointCount(), 3 * kGridPoints);
  EXPECT_EQ(map.leafCount(), kGridPoints);
  for (std::size_t s = 0; s < 3; ++s) EXPECT_EQ(store.at(s).points.size(), kGridPoints);
  EXPECT_TRUE(store.at(3).points.empty());
  EXPECT_EQ(map.pointsInLeafAt(Eigen::Vector3d(10.0, 0.0, 0.0)), 0u);
  // Rebuilding again with unchanged poses changes nothing.
  const RebuildReport again = map.rebuild(store);
  EXPECT_EQ(again.sparse_leaves_removed, 0u);
  EXPECT_EQ(again.kept_points, 3 * kGridPoints);
}

TEST(PointMap, RebuildKeepsASurfaceSeenByASingleKeyframe) {
  // At 2 m the 10 px grid samples the plane every 4 cm (2 leaves): one point per leaf, but the
  // surface is not isolated, so it survives the rebuild.
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  Keyframe kf;
  kf.points = map.insertKeyframe(planeFrame(2000), kf.T_world_cam);
  store.add(kf);
  const RebuildReport r = map.rebuild(store);
  EXPECT_EQ(r.sparse_points_removed, 0u);
  EXPECT_EQ(r.kept_points, kGridPoints);
}

TEST(PointMap, RebuildUsesCorrectedPoses) {
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  const RgbdFrame f = planeFrame(2000);
  for (std::uint64_t id = 0; id < 3; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.points = map.insertKeyframe(f, kf.T_world_cam);
    store.add(kf);
  }
  const std::vector<WorldPoint> before = map.points();
  // A pose-graph correction moves every keyframe by the same rigid motion: the map moves with it.
  Eigen::Isometry3d correction = translation(1.0, 0.5, 0.0);
  correction.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (std::uint64_t id = 0; id < 3; ++id)
    store.setPose(id, correction * store.get(id).T_world_cam);
  EXPECT_TRUE(map.isOutdated(store));
  const RebuildReport r = map.rebuild(store);
  EXPECT_FALSE(map.isOutdated(store));
  ASSERT_EQ(r.kept_points, 3 * kGridPoints);
  ASSERT_EQ(map.pointCount(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    const Eigen::Vector3d expected = correction * before[i].p_world.cast<double>();
    ASSERT_LT((map.points()[i].p_world.cast<double>() - expected).norm(), 1e-5) << i;
    ASSERT_EQ(map.points()[i].rgb, before[i].rgb);
  }
}

TEST(PointMap, AKeyframeMovedAwayByALoopClosureTakesItsSurfaceAlong) {
  // Three keyframes see one plane; a loop closure moves the third 10 m away. Its plane is a
  // surface there too (not isolated), so it is kept; the first two keep theirs (2 per leaf).
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  const RgbdFrame f = planeFrame(2000);
  for (std::uint64_t id = 0; id < 3; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.points = map.insertKeyframe(f, kf.T_world_cam);
    store.add(kf);
  }
  store.setPose(2, translation(0.0, 0.0, 10.0));
  const RebuildReport r = map.rebuild(store);
  EXPECT_EQ(r.kept_points, 3 * kGridPoints);
  EXPECT_EQ(r.sparse_leaves_removed, 0u);
  EXPECT_EQ(map.leafCount(), 2 * kGridPoints);
  for (std::size_t s = 0; s < 3; ++s) EXPECT_EQ(store.at(s).points.size(), kGridPoints);
  EXPECT_EQ(map.pointsInLeafAt(Eigen::Vector3d(0, 0, 12.0) +
                               Eigen::Vector3d(map.points().front().p_world.x(),
                                               map.points().front().p_world.y(), 0.0)),
            1u);
}

TEST(PointMap, RebuildMatchesTheReferenceOnRandomKeyframesAndPoseUpdates) {
  std::mt19937_64 rng(7);
  MappingOptions o;  // capacity 5, min 3
  PointMap map(o);
  KeyframeStore store;
  for (std::uint64_t id = 0; id < 30; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.T_world_cam = randomPose(rng, 0.05, 0.05);
    kf.points = map.insertPoints(randomCloud(rng, 1500, 0.15), kf.T_world_cam);
    store.add(kf);
  }
  {  // and stray points half a metre apart, far from the cloud: isolated
    Keyframe kf;
    kf.id = 30;
    std::vector<MapPoint> stray(10);
    for (int i = 0; i < 10; ++i) stray[i].p_cam = Eigen::Vector3f(5.0f + 0.5f * i, 0.0f, 0.0f);
    kf.points = map.insertPoints(stray, kf.T_world_cam);
    store.add(kf);
  }
  // Perturb every pose (a "loop closure"), then rebuild; compare with the reference rules.
  for (std::uint64_t id = 0; id <= 30; ++id)
    store.setPose(id, randomPose(rng, 0.02, 0.02) * store.get(id).T_world_cam);
  std::vector<std::vector<MapPoint>> expected(store.size());
  ReferenceMap ref(o.octree_resolution_m, o.max_points_per_leaf);
  std::vector<std::vector<char>> accepted(store.size());
  for (std::size_t s = 0; s < store.size(); ++s)
    for (const MapPoint& p : store.at(s).points)
      accepted[s].push_back(ref.insert(store.at(s).T_world_cam * p.p_cam.cast<double>()));
  std::size_t expected_total = 0;
  for (std::size_t s = 0; s < store.size(); ++s)
    for (std::size_t i = 0; i < store.at(s).points.size(); ++i) {
      const MapPoint& p = store.at(s).points[i];
      if (accepted[s][i] &&
          ref.neighbourhoodCount(store.at(s).T_world_cam * p.p_cam.cast<double>()) >= 3) {
        expected[s].push_back(p);
        ++expected_total;
      }
    }
  const RebuildReport r = map.rebuild(store);
  EXPECT_GT(r.rejected_full_leaf, 0u);
  EXPECT_GT(r.sparse_points_removed, 0u);
  EXPECT_EQ(r.kept_points, expected_total);
  EXPECT_EQ(map.pointCount(), expected_total);
  for (std::size_t s = 0; s < store.size(); ++s) {
    ASSERT_EQ(store.at(s).points.size(), expected[s].size()) << s;
    for (std::size_t i = 0; i < expected[s].size(); ++i)
      ASSERT_TRUE(samePoint(store.at(s).points[i], expected[s][i]));
  }
  for (const WorldPoint& p : map.points()) {
    const std::size_t n = map.pointsInLeafAt(p.p_world.cast<double>());
    ASSERT_GE(n, 1u);
    ASSERT_LE(n, 5u);
  }
}

TEST(PointMap, TheIsolatedLeafRuleCountsNeighboursAcrossCellBlockBordersAndNegativeKeys) {
  // Sparse random points around the origin, where the keys change sign and the map's blocks
  // of 4 x 4 x 4 cells (16 cm at 2 cm) meet: about 3 points per neighbourhood, so the rule's
  // verdicts depend on cells of every neighbouring block. rebuild() and update() after every
  // keyframe moved must keep exactly the points the independent reference keeps.
  for (int min_count : {2, 3, 4}) {
    SCOPED_TRACE("min " + std::to_string(min_count));
    std::mt19937_64 rng(100 + min_count);
    MappingOptions o;
    o.min_points_per_leaf_rebuild = min_count;
    PointMap rebuilt(o), updated(o);
    KeyframeStore store;
    std::uniform_real_distribution<float> u(-0.3f, 0.3f);
    for (std::uint64_t id = 0; id < 40; ++id) {
      Keyframe kf;
      kf.id = id;
      std::vector<MapPoint> cloud(10);
      for (MapPoint& p : cloud) p.p_cam = Eigen::Vector3f(u(rng), u(rng), u(rng));
      kf.points = rebuilt.insertPoints(cloud, kf.T_world_cam);
      updated.insertPoints(cloud, kf.T_world_cam, id);
      store.add(kf);
    }
    std::vector<std::uint64_t> moved;
    for (std::uint64_t id = 0; id < 40; ++id) {
      store.setPose(id, randomPose(rng, 0.05, 0.1) * store.get(id).T_world_cam);
      moved.push_back(id);
    }
    ReferenceMap ref(o.octree_resolution_m, o.max_points_per_leaf);
    std::vector<std::vector<char>> accepted(store.size());
    for (std::size_t s = 0; s < store.size(); ++s)
      for (const MapPoint& p : store.at(s).points)
        accepted[s].push_back(ref.insert(store.at(s).T_world_cam * p.p_cam.cast<double>()));
    std::vector<std::vector<MapPoint>> expected(store.size());
    std::size_t expected_total = 0, isolated = 0;
    for (std::size_t s = 0; s < store.size(); ++s)
      for (std::size_t i = 0; i < store.at(s).points.size(); ++i) {
        const MapPoint& p = store.at(s).points[i];
        if (!accepted[s][i]) continue;
        if (ref.neighbourhoodCount(store.at(s).T_world_cam * p.p_cam.cast<double>()) < min_count) {
          ++isolated;
          continue;
        }
        expected[s].push_back(p);
        ++expected_total;
      }
    ASSERT_GT(isolated, 20u);  // the rule decides for many points
    ASSERT_GT(expected_total, 100u);
    KeyframeStore store_updated = store;
    EXPECT_EQ(rebuilt.rebuild(store).kept_points, expected_total);
    EXPECT_EQ(updated.update(store_updated, moved).kept_points, expected_total);
    for (const KeyframeStore* st : {&store, &store_updated})
      for (std::size_t s = 0; s < st->size(); ++s) {
        ASSERT_EQ(st->at(s).points.size(), expected[s].size()) << s;
        for (std::size_t i = 0; i < expected[s].size(); ++i)
          ASSERT_TRUE(samePoint(st->at(s).points[i], expected[s][i]));
      }
    EXPECT_EQ(rebuilt.leafCount(), updated.leafCount());
  }
}

TEST(PointMap, RepeatedViewsOfOneRegionDoNotGrowTheMapBeyondLeavesTimesCapacity) {
  std::mt19937_64 rng(3);
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 12; ++k) poses.push_back(randomPose(rng, 0.05, 0.03));
  PointMap map{MappingOptions{}};
  KeyframeStore store;
  const RgbdFrame f = planeFrame(2500);
  std::size_t count_after_saturation = 0, bytes_after_saturation = 0;
  std::uint64_t id = 0;
  for (int lap = 0; lap < 10; ++lap) {
    for (const Eigen::Isometry3d& T : poses) {
      Keyframe kf;
      kf.id = id++;
      kf.T_world_cam = T;
      kf.points = map.insertKeyframe(f, T);
      store.add(std::move(kf));
      ASSERT_LE(map.pointCount(), map.leafCount() * 5);
    }
    // Each view revisits its own leaves, which are full after 5 laps: nothing grows after that.
    if (lap == 5) {
      count_after_saturation = map.pointCount();
      bytes_after_saturation = map.memoryBytes();
    }
  }
  EXPECT_EQ(map.pointCount(), count_after_saturation);
  EXPECT_EQ(map.memoryBytes(), bytes_after_saturation);
  EXPECT_EQ(store.pointCount(), map.pointCount());  // keyframes keep exactly the map's points
  for (std::size_t s = 6 * poses.size(); s < store.size(); ++s)
    EXPECT_TRUE(store.at(s).points.empty());
  // Estimated memory: points, leaves and nodes, far below the images a keyframe would hold.
  EXPECT_GT(map.memoryBytes(), map.pointCount() * sizeof(WorldPoint));
  EXPECT_LT(map.memoryBytes(), map.pointCount() * 200);
  EXPECT_LT(store.at(0).memoryBytes(), kGridPoints * sizeof(MapPoint) + 1024);
}

TEST(PointMap, NonAlignedDepthUsesDepthIntrinsicsAndTheColourExtrinsic) {
  RgbdFrame f;
  f.cam_color = makeCamera(640, 480, 520.0);
  f.cam_depth = makeCamera(600, 470, 400.0);
  f.cam_depth.cx = 300.3;
  f.cam_depth.cy = 231.7;
  f.depth_aligned_to_color = false;
  f.T_color_depth = translation(-0.025, 0.002, 0.001);
  f.T_color_depth.linear() =
      Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.3, 1.0, 0.1).normalized()).toRotationMatrix();
  f.depth = cv::Mat(470, 600, CV_16UC1, cv::Scalar(1800));
  f.rgb = rgbdi::mapping::test::patternImage(640, 480);
  f.depth_unit_m = 1e-3;
  PointMap map{MappingOptions{}};
  const std::vector<MapPoint> kept = map.insertKeyframe(f, Eigen::Isometry3d::Identity());
  // Columns 40..590 and rows 10..460 fit into 600x470.
  ASSERT_EQ(kept.size(), kGridPoints);
  int coloured = 0, outside = 0;
  for (std::size_t r = 0; r < kGridRows; ++r)
    for (std::size_t c = 0; c < kGridCols; ++c) {
      const int u = 40 + 10 * static_cast<int>(c), v = 10 + 10 * static_cast<int>(r);
      const Eigen::Vector3d p_depth((u - 300.3) / 400.0 * 1.8, (v - 231.7) / 400.0 * 1.8, 1.8);
      const Eigen::Vector3d expected = f.T_color_depth * p_depth;
      const MapPoint& p = kept[r * kGridCols + c];
      EXPECT_LT((p.p_cam.cast<double>() - expected).norm(), 1e-5);
      Eigen::Vector2d uv;
      ASSERT_TRUE(f.cam_color.project(expected, uv));
      const int cu = static_cast<int>(std::lround(uv.x())),
                cv_ = static_cast<int>(std::lround(uv.y()));
      if (cu >= 0 && cv_ >= 0 && cu < 640 && cv_ < 480) {
        const cv::Vec3b colour = pixelColour(cu, cv_);
        EXPECT_EQ(p.rgb, (Rgb{colour[0], colour[1], colour[2]})) << u << "," << v;
        ++coloured;
      } else {
        EXPECT_EQ(p.rgb, kUncolouredRgb) << u << "," << v;  // outside the colour camera's view
        ++outside;
      }
    }
  EXPECT_GT(coloured, 1000);
  EXPECT_GT(outside, 100);
  // Points that project outside the colour image are grey; without colour image all are grey.
  f.rgb.release();
  PointMap grey{MappingOptions{}};
  for (const MapPoint& p : grey.insertKeyframe(f, Eigen::Isometry3d::Identity()))
    ASSERT_EQ(p.rgb, kUncolouredRgb);
}

TEST(PointMap, DistortedCamerasBackProjectOntoTheGridPixels) {
  PinholeCamera cam = makeCamera();
  cam.dist = {0.12, -0.25, 0.001, -0.0015, 0.05};
  PointMap map{MappingOptions{}};
  const std::vector<MapPoint> kept =
      map.insertKeyframe(planeFrame(3000, cam), Eigen::Isometry3d::Identity());
  ASSERT_EQ(kept.size(), kGridPoints);
  for (std::size_t r = 0; r < kGridRows; ++r)
    for (std::size_t c = 0; c < kGridCols; ++c) {
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.project(kept[r * kGridCols + c].p_cam.cast<double>(), uv));
      ASSERT_NEAR(uv.x(), 40 + 10.0 * c, 2e-3);
      ASSERT_NEAR(uv.y(), 10 + 10.0 * r, 2e-3);
    }
}

TEST(PointMap, SmallImagesClipTheGridAndBadFramesAreRejectedWithTheirSource) {
  PointMap map{MappingOptions{}};
  // 320x240: u 40..310, v 10..230.
  EXPECT_EQ(map.insertKeyframe(planeFrame(2000, makeCamera(320, 240, 250.0)),
                               Eigen::Isometry3d::Identity())
                .size(),
            28u * 23u);

  const std::string label = "seq.rawlog record 7";
  RgbdFrame f = planeFrame(2000, makeCamera(), label);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  auto expectError = [&](RgbdFrame frame, const Eigen::Isometry3d& T, const std::string& part) {
    const std::string e = errorOf([&] { map.insertKeyframe(frame, T); });
    EXPECT_NE(e.find(label), std::string::npos) << e;
    EXPECT_NE(e.find(part), std::string::npos) << e;
  };
  RgbdFrame g = f;
  g.depth.release();
  expectError(g, I, "no depth image");
  g = f;
  f.depth.convertTo(g.depth, CV_32F);
  expectError(g, I, "CV_16UC1");
  g = f;
  g.rgb = cv::Mat(240, 320, CV_8UC3);
  expectError(g, I, "colour image is 320x240");
  g = f;
  g.cam_color = makeCamera(30, 20);
  g.depth = cv::Mat(20, 30, CV_16UC1, cv::Scalar(1000));
  g.rgb.release();
  expectError(g, I, "sampling grid");
  g = f;
  g.depth_unit_m = 0.0;
  expectError(g, I, "depth_unit_m");
  Eigen::Isometry3d scaled = I;
  scaled.linear() *= 1.1;
  expectError(f, scaled, "rigid");
  Eigen::Isometry3d nan_pose = I;
  nan_pose.translation().x() = std::nan("");
  expectError(f, nan_pose, "rigid");
  EXPECT_EQ(map.stats().keyframes, 1u);  // rejected frames leave the map untouched
}
