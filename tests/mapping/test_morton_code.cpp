// Morton code of OctoMap keys: the order in which the occupancy map updates its cells.
#include <gtest/gtest.h>
#include <octomap/OcTreeKey.h>

#include <cstdint>
#include <random>

#include "rgbdi/mapping/morton_code.h"

using rgbdi::mapping::detail::mortonCode;

TEST(MortonCode, InterleavesTheCoordinateBitsXFirst) {
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0, 0, 0)), 0u);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(1, 0, 0)), 1u);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0, 1, 0)), 2u);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0, 0, 1)), 4u);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(2, 0, 0)), 8u);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0x8000, 0, 0)), std::uint64_t{1} << 45);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0, 0, 0x8000)), std::uint64_t{1} << 47);
  EXPECT_EQ(mortonCode(octomap::OcTreeKey(0xFFFF, 0xFFFF, 0xFFFF)), (std::uint64_t{1} << 48) - 1);
}

TEST(MortonCode, EachBitTripleIsOctomapsChildIndexAtThatLevel) {
  // Sorting by the code therefore lists keys in the tree's depth-first order (root level first).
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> coord(0, 0xFFFF);
  for (int n = 0; n < 1000; ++n) {
    const octomap::OcTreeKey k(static_cast<octomap::key_type>(coord(rng)),
                               static_cast<octomap::key_type>(coord(rng)),
                               static_cast<octomap::key_type>(coord(rng)));
    const std::uint64_t code = mortonCode(k);
    for (int bit = 0; bit < 16; ++bit)
      ASSERT_EQ((code >> (3 * bit)) & 7u, octomap::computeChildIdx(k, bit)) << "bit " << bit;
  }
}
