// PointMap::update (the map after a loop, touching only the moved keyframes) against
// PointMap::rebuild (everything re-inserted) on the same stores: same leaves, same points, same
// kept points per keyframe, same report counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <tuple>
#include <vector>

#include "rgbdi/mapping/point_map.h"

using namespace rgbdi;
using namespace rgbdi::mapping;

namespace {

Eigen::Isometry3d randomPose(std::mt19937_64& rng, double trans, double rot_rad) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
  T.linear() = Eigen::AngleAxisd(rot_rad * u(rng), axis).toRotationMatrix();
  T.translation() = trans * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return T;
}

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

using PointKey = std::tuple<float, float, float, int, int, int, std::size_t>;

/// Every map point with the count of its leaf, sorted (the order of points() is not compared).
std::vector<PointKey> pointsWithLeafCounts(const PointMap& map) {
  std::vector<PointKey> out;
  for (const WorldPoint& p : map.points())
    out.emplace_back(p.p_world.x(), p.p_world.y(), p.p_world.z(), p.rgb[0], p.rgb[1], p.rgb[2],
                     map.pointsInLeafAt(p.p_world.cast<double>()));
  std::sort(out.begin(), out.end());
  return out;
}

/// Leaf centres with their counts, sorted.
std::vector<std::tuple<double, double, double, std::size_t>> leaves(const PointMap& map) {
  std::vector<std::tuple<double, double, double, std::size_t>> out;
  for (const WorldPoint& p : map.points()) {
    const Eigen::Vector3d c = map.leafCenterAt(p.p_world.cast<double>());
    out.emplace_back(c.x(), c.y(), c.z(), map.pointsInLeafAt(p.p_world.cast<double>()));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

void expectSameStores(const KeyframeStore& a, const KeyframeStore& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t s = 0; s < a.size(); ++s) {
    const Keyframe &ka = a.at(s), &kb = b.at(s);
    ASSERT_EQ(ka.id, kb.id);
    ASSERT_TRUE(ka.T_world_cam.matrix() == kb.T_world_cam.matrix());
    ASSERT_EQ(ka.points.size(), kb.points.size()) << "keyframe " << ka.id;
    for (std::size_t i = 0; i < ka.points.size(); ++i) {
      ASSERT_TRUE(ka.points[i].p_cam == kb.points[i].p_cam) << ka.id << " point " << i;
      ASSERT_EQ(ka.points[i].rgb, kb.points[i].rgb);
    }
  }
}

void expectSameReports(const RebuildReport& a, const RebuildReport& b) {
  EXPECT_EQ(a.keyframes, b.keyframes);
  EXPECT_EQ(a.input_points, b.input_points);
  EXPECT_EQ(a.rejected_full_leaf, b.rejected_full_leaf);
  EXPECT_EQ(a.outside_extent, b.outside_extent);
  EXPECT_EQ(a.sparse_leaves_removed, b.sparse_leaves_removed);
  EXPECT_EQ(a.sparse_points_removed, b.sparse_points_removed);
  EXPECT_EQ(a.kept_points, b.kept_points);
}

/// Adds keyframe `id`: a dense cloud (full leaves), a sparse one (isolated leaves) and, for some,
/// points beyond the octree's extent once moved far.
void addKeyframe(std::mt19937_64& rng, PointMap& map, KeyframeStore& store, std::uint64_t id) {
  Keyframe kf;
  kf.id = id;
  kf.T_world_cam = randomPose(rng, 0.1, 0.1);
  std::vector<MapPoint> pts = randomCloud(rng, 800, 0.08);
  const std::vector<MapPoint> sparse = randomCloud(rng, 60, 0.8);
  pts.insert(pts.end(), sparse.begin(), sparse.end());
  kf.points = map.insertPoints(pts, kf.T_world_cam, id);
  store.add(std::move(kf));
}

/// Moves each keyframe with probability `share` (small corrections, now and then a large one)
/// and returns the moved ids.
std::vector<std::uint64_t> moveSome(std::mt19937_64& rng, KeyframeStore& store, double share) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::uint64_t> moved;
  for (const Keyframe& kf : std::vector<Keyframe>(store.keyframes())) {
    if (u(rng) >= share) continue;
    const bool large = u(rng) < 0.1;
    store.setPose(kf.id, randomPose(rng, large ? 0.5 : 0.03, large ? 0.3 : 0.03) * kf.T_world_cam);
    moved.push_back(kf.id);
  }
  return moved;
}

}  // namespace

TEST(PointMapUpdate, GivesTheLeavesPointsAndKeptPointsOfAFullRebuild) {
  for (const auto& [capacity, min_count] : {std::pair{5, 3}, {1, 1}, {3, 0}, {6, 6}}) {
    SCOPED_TRACE("capacity " + std::to_string(capacity) + ", min " + std::to_string(min_count));
    std::mt19937_64 rng(11 + capacity);
    MappingOptions o;
    o.max_points_per_leaf = capacity;
    o.min_points_per_leaf_rebuild = min_count;
    PointMap map(o);
    KeyframeStore store;
    std::uint64_t next_id = 0;
    for (; next_id < 25; ++next_id) addKeyframe(rng, map, store, next_id);
    std::size_t evicted_total = 0, sparse_total = 0;
    // Rounds of "loops" of different sizes, with new keyframes in between (insertions since the
    // last isolated-leaf pass must be covered too; the last round moves nothing).
    for (const double share : {0.1, 0.5, 1.0, 0.3, 0.0}) {
      SCOPED_TRACE("share moved " + std::to_string(share));
      const std::vector<std::uint64_t> moved = moveSome(rng, store, share);
      KeyframeStore reference_store = store;  // the same inputs for the full rebuild
      PointMap reference(o);
      const RebuildReport full = reference.rebuild(reference_store);
      const RebuildReport incremental = map.update(store, moved);
      expectSameReports(incremental, full);
      EXPECT_EQ(map.pointCount(), reference.pointCount());
      EXPECT_EQ(map.leafCount(), reference.leafCount());
      EXPECT_EQ(store.pointCount(), map.pointCount());
      EXPECT_TRUE(pointsWithLeafCounts(map) == pointsWithLeafCounts(reference));
      EXPECT_TRUE(leaves(map) == leaves(reference));
      expectSameStores(store, reference_store);
      EXPECT_FALSE(map.isOutdated(store));
      evicted_total += full.rejected_full_leaf;
      sparse_total += full.sparse_points_removed;
      for (int k = 0; k < 3; ++k, ++next_id) addKeyframe(rng, map, store, next_id);
    }
    // The rounds exercised both rules (points not fitting a full leaf, isolated leaves).
    if (capacity > 1) EXPECT_GT(evicted_total, 0u);
    if (min_count > 1) EXPECT_GT(sparse_total, 0u);
  }
}

TEST(PointMapUpdate, AMovedKeyframeWithALowerIdTakesTheFullLeafFromALaterOne) {
  // Capacity 1: keyframe 0 has a point in leaf A, keyframe 1 one in leaf B. A correction moves
  // keyframe 0 onto B: a rebuild inserts keyframe 0 first, so keyframe 1 loses its point.
  MappingOptions o;
  o.max_points_per_leaf = 1;
  o.min_points_per_leaf_rebuild = 0;
  PointMap map(o);
  KeyframeStore store;
  MapPoint p;
  p.p_cam = Eigen::Vector3f(0.011f, 0.011f, 2.011f);
  for (std::uint64_t id = 0; id < 2; ++id) {
    Keyframe kf;
    kf.id = id;
    kf.T_world_cam.translation() = Eigen::Vector3d(0.1 * static_cast<double>(id), 0, 0);
    kf.points = map.insertPoints({p}, kf.T_world_cam, id);
    ASSERT_EQ(kf.points.size(), 1u);
    store.add(kf);
  }
  Eigen::Isometry3d onto_b = Eigen::Isometry3d::Identity();
  onto_b.translation() = Eigen::Vector3d(0.1, 0, 0);
  store.setPose(0, onto_b);
  const RebuildReport r = map.update(store, {0});
  EXPECT_EQ(r.rejected_full_leaf, 1u);
  EXPECT_EQ(r.kept_points, 1u);
  EXPECT_EQ(map.leafCount(), 1u);
  EXPECT_EQ(store.get(0).points.size(), 1u);
  EXPECT_TRUE(store.get(1).points.empty());
  // Moving keyframe 1 back does not bring its point back: it was dropped like in a rebuild.
  EXPECT_EQ(map.update(store, {1}).kept_points, 1u);
}

TEST(PointMapUpdate, RefusesPointsOfUnknownOriginAndStoresThatDisagreeWithTheMap) {
  MappingOptions o;
  std::mt19937_64 rng(3);
  {
    PointMap map(o);
    KeyframeStore store;
    Keyframe kf;
    kf.points = map.insertPoints(randomCloud(rng, 100, 0.1), kf.T_world_cam);  // no id
    store.add(kf);
    EXPECT_THROW(map.update(store, {0}), std::logic_error);
    map.rebuild(store);  // a rebuild knows every point's keyframe: update works afterwards
    EXPECT_NO_THROW(map.update(store, {0}));
  }
  {
    PointMap map(o);
    KeyframeStore store;
    Keyframe kf;
    kf.id = 4;
    kf.points = map.insertPoints(randomCloud(rng, 100, 0.1), kf.T_world_cam, 4);
    kf.points.pop_back();  // the store does not hold what the map inserted
    store.add(kf);
    EXPECT_THROW(map.update(store, {4}), std::logic_error);
    EXPECT_THROW(map.update(store, {5}), std::invalid_argument);
    KeyframeStore other;
    EXPECT_THROW(map.update(other, {}), std::logic_error);  // keyframe 4 is not in that store
  }
}
