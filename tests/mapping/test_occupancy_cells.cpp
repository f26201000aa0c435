// The occupancy map's per-scan cells and batch tree update against OctoMap's own calls
// (computeDiscreteUpdate with KeySets, updateNode per cell): the same trees, node for node.
#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <vector>

#include "rgbdi/mapping/morton_code.h"
#include "rgbdi/mapping/occupancy_cells.h"

namespace {
using rgbdi::mapping::detail::keyOfMortonCode;
using rgbdi::mapping::detail::mortonCode;
using rgbdi::mapping::detail::MortonSet;
using rgbdi::mapping::detail::OccupancyTree;
using rgbdi::mapping::detail::ScanCells;
using rgbdi::mapping::detail::sortMortonCodes;

constexpr double kResolution = 0.05;
constexpr double kMaxRange = 3.0;

struct Scan {
  octomap::point3d origin;
  std::vector<octomap::point3d> rays, hits;
};

/// Endpoints in a box ahead of a camera at `origin` (x forward [m], half width [m]): by default
/// 1.5-4 m deep, some beyond the maximum range.
Scan randomScan(std::mt19937& rng, const octomap::point3d& origin, float near = 1.5f,
                float far = 4.0f, float half_width = 1.2f) {
  std::uniform_real_distribution<float> lateral(-half_width, half_width), depth(near, far);
  Scan s;
  s.origin = origin;
  for (int i = 0; i < 400; ++i) {
    const octomap::point3d p = origin + octomap::point3d(depth(rng), lateral(rng), lateral(rng));
    (i % 4 == 0 ? s.rays : s.hits).push_back(p);
  }
  return s;
}

/// A scan's cells by OctoMap's own calls: what castRays computed before ScanCells.
void referenceCells(octomap::OcTree& tree, const Scan& s, octomap::KeySet& free_cells,
                    octomap::KeySet& occupied_cells) {
  octomap::Pointcloud cloud;
  for (const octomap::point3d& p : s.rays) cloud.push_back(p);
  tree.computeDiscreteUpdate(cloud, s.origin, free_cells, occupied_cells, kMaxRange);
  for (const octomap::point3d& p : s.hits) {
    octomap::OcTreeKey key;
    if ((p - s.origin).norm() <= kMaxRange && tree.coordToKeyChecked(p, key)) {
      occupied_cells.insert(key);
      free_cells.erase(key);
    }
  }
}

/// What castRays did before ScanCells and updateSorted: OctoMap's updateNode per cell.
void referenceInsert(octomap::OcTree& tree, const Scan& s) {
  octomap::KeySet free_cells, occupied_cells;
  referenceCells(tree, s, free_cells, occupied_cells);
  for (const octomap::OcTreeKey& k : free_cells) tree.updateNode(k, false, true);
  for (const octomap::OcTreeKey& k : occupied_cells) tree.updateNode(k, true, true);
}

void ourInsert(OccupancyTree& tree, ScanCells& cells, const Scan& s) {
  cells.compute(tree, s.origin, s.rays, s.hits, kMaxRange);
  tree.updateSorted(cells.freeCells(), tree.getProbMissLog());
  tree.updateSorted(cells.occupiedCells(), tree.getProbHitLog());
}

void expectSameTree(octomap::OcTree& ours, octomap::OcTree& reference) {
  ours.updateInnerOccupancy();
  reference.updateInnerOccupancy();
  ASSERT_EQ(ours.size(), reference.size());
  ASSERT_EQ(ours.getNumLeafNodes(), reference.getNumLeafNodes());
  for (auto it = reference.begin_leafs(); it != reference.end_leafs(); ++it) {
    const octomap::OcTreeNode* n = ours.search(it.getKey(), it.getDepth());
    ASSERT_NE(n, nullptr);
    ASSERT_EQ(n->getLogOdds(), it->getLogOdds());
  }
  std::ostringstream ours_bytes, reference_bytes;
  ASSERT_TRUE(ours.write(ours_bytes));
  ASSERT_TRUE(reference.write(reference_bytes));
  EXPECT_EQ(ours_bytes.str(), reference_bytes.str());
}
}  // namespace

TEST(MortonCode, KeyOfMortonCodeInvertsMortonCode) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(0, 0xFFFF);
  for (int n = 0; n < 1000; ++n) {
    const octomap::OcTreeKey k(static_cast<octomap::key_type>(coord(rng)),
                               static_cast<octomap::key_type>(coord(rng)),
                               static_cast<octomap::key_type>(coord(rng)));
    ASSERT_EQ(keyOfMortonCode(mortonCode(k)), k);
  }
  EXPECT_EQ(keyOfMortonCode((std::uint64_t{1} << 48) - 1),
            octomap::OcTreeKey(0xFFFF, 0xFFFF, 0xFFFF));
}

TEST(MortonSet, KeepsEachCodeOnceInInsertionOrderAcrossGrowthAndClear) {
  MortonSet set;
  std::vector<std::uint64_t> expected;
  // Enough codes to grow the table several times; every code is offered twice.
  for (std::uint64_t i = 0; i < 20000; ++i) {
    const std::uint64_t code = (i * 7919u) % 30011u;  // distinct for i < 30011
    EXPECT_TRUE(set.insert(code));
    EXPECT_FALSE(set.insert(code));
    expected.push_back(code);
  }
  EXPECT_EQ(set.codes(), expected);
  // Reordering the codes (as ScanCells sorts them) does not disturb the table.
  std::sort(set.codes().begin(), set.codes().end());
  EXPECT_FALSE(set.insert(expected[123]));
  EXPECT_TRUE(set.insert(30011u));
  set.clear();
  EXPECT_TRUE(set.codes().empty());
  EXPECT_TRUE(set.insert(expected[1]));
  EXPECT_TRUE(set.insert(expected[0]));
  EXPECT_FALSE(set.insert(expected[0]));
  EXPECT_EQ(set.codes(), (std::vector<std::uint64_t>{expected[1], expected[0]}));
}

TEST(MortonCode, RadixSortOrdersCodesAsStdSort) {
  // Codes over all 48 bits, codes whose high digits are one value (the skipped passes), an odd
  // number of real passes (the result ends in the scratch buffer), duplicates, and 0 / 1 codes.
  std::mt19937_64 rng(5);
  std::vector<std::uint64_t> scratch;
  const std::uint64_t masks[] = {(std::uint64_t{1} << 48) - 1, 0xFFFF, 0xFF00FF, 0xFF, 0xFFFFFF};
  for (const std::uint64_t mask : masks)
    for (const std::size_t n :
         {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{5000}}) {
      std::vector<std::uint64_t> codes(n);
      for (std::uint64_t& c : codes) c = (rng() & mask) | (std::uint64_t{0x5A} << 40);
      if (n > 10) codes[3] = codes[7];  // a duplicate
      std::vector<std::uint64_t> expected = codes;
      std::sort(expected.begin(), expected.end());
      sortMortonCodes(codes, scratch);
      EXPECT_EQ(codes, expected) << "mask " << mask << ", n " << n;
    }
}

TEST(ScanCells, SameCellsAsOctomapsDiscreteUpdateSortedAndDisjoint) {
  std::mt19937 rng(11);
  octomap::OcTree tree(kResolution);
  ScanCells cells;
  for (int n = 0; n < 3; ++n) {  // the kept buffers must not leak cells from scan to scan
    const Scan s = randomScan(rng, octomap::point3d(0.1f * n, -0.2f, 0.3f));
    octomap::KeySet free_cells, occupied_cells;
    referenceCells(tree, s, free_cells, occupied_cells);
    std::vector<std::uint64_t> free_expected, occupied_expected;
    for (const octomap::OcTreeKey& k : free_cells) free_expected.push_back(mortonCode(k));
    for (const octomap::OcTreeKey& k : occupied_cells) occupied_expected.push_back(mortonCode(k));
    std::sort(free_expected.begin(), free_expected.end());
    std::sort(occupied_expected.begin(), occupied_expected.end());

    cells.compute(tree, s.origin, s.rays, s.hits, kMaxRange);
    EXPECT_EQ(cells.freeCells(), free_expected);
    EXPECT_EQ(cells.occupiedCells(), occupied_expected);
    EXPECT_GT(free_expected.size(), 1000u);
    EXPECT_GT(occupied_expected.size(), 100u);
  }
}

TEST(OccupancyTree, ScansGiveOctomapsTreeNodeForNodeIncludingClampedCells) {
  // Overlapping scans from nearby poses: cells are hit and missed many times, so the clamping
  // thresholds are reached (OctoMap's early abort) and crossed in both directions.
  std::mt19937 rng(5);
  OccupancyTree ours(kResolution);
  octomap::OcTree reference(kResolution);
  ScanCells cells;
  for (int n = 0; n < 25; ++n) {
    // Every other scan onto a small patch, 2 m ahead: its cells are hit often enough to clamp.
    const Scan s =
        n % 2 ? randomScan(rng, octomap::point3d(0.0f, 0.01f * (n % 5), 0.0f), 1.95f, 2.05f, 0.2f)
              : randomScan(rng, octomap::point3d(0.02f * n, 0.0f, 0.0f));
    ourInsert(ours, cells, s);
    referenceInsert(reference, s);
  }
  std::size_t at_max = 0, at_min = 0;
  for (auto it = reference.begin_leafs(); it != reference.end_leafs(); ++it) {
    at_max += it->getLogOdds() == reference.getClampingThresMaxLog();
    at_min += it->getLogOdds() == reference.getClampingThresMinLog();
  }
  EXPECT_GT(at_max, 10u);
  EXPECT_GT(at_min, 100u);
  expectSameTree(ours, reference);
}

TEST(OccupancyTree, PrunedNodesAreExpandedOrLeftAloneAsByOctomapsUpdateNode) {
  // A tree with pruned nodes (not made by the occupancy map itself, which never prunes, but
  // possible in a tree given to it): a pruned node clamped in the update's direction is left as
  // it is, any other is expanded.
  std::mt19937 rng(9);
  OccupancyTree ours(kResolution);
  octomap::OcTree reference(kResolution);
  ScanCells cells;
  for (int n = 0; n < 30; ++n) {
    const Scan s = randomScan(rng, octomap::point3d(0.0f, 0.0f, 0.0f));
    ourInsert(ours, cells, s);
    referenceInsert(reference, s);
  }
  ours.updateInnerOccupancy();
  reference.updateInnerOccupancy();
  const std::size_t unpruned_size = reference.size();
  ours.prune();
  reference.prune();
  const std::size_t pruned_size = reference.size();
  ASSERT_EQ(ours.size(), pruned_size);
  ASSERT_LT(pruned_size, unpruned_size);
  // Then scans from elsewhere, through the pruned free space and onto it.
  for (int n = 0; n < 5; ++n) {
    const Scan s = randomScan(rng, octomap::point3d(0.5f, 0.3f * n, 0.1f));
    ourInsert(ours, cells, s);
    referenceInsert(reference, s);
  }
  EXPECT_NE(reference.size(), pruned_size);
  expectSameTree(ours, reference);
}
