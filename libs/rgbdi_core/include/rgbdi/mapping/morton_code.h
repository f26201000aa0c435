// Morton (Z-order) code of an OctoMap key: the bits of the three 16-bit coordinates interleaved,
// most significant level first, x in the lowest bit of each triple as OctoMap's child index
// (computeChildIdx: x = 1, y = 2, z = 4). Sorting keys by it lists the leaves in the tree's
// depth-first order, so that consecutive updates share the path from the root.
#pragma once

#include <octomap/OcTreeKey.h>

#include <cstdint>

namespace rgbdi::mapping::detail {

/// Spreads the 16 bits of v to every third bit (bit i goes to bit 3i).
inline std::uint64_t spreadBits3(std::uint64_t v) {
  v &= 0xFFFFu;
  v = (v | (v << 16)) & 0x0000FF0000FFull;
  v = (v | (v << 8)) & 0x00F00F00F00Full;
  v = (v | (v << 4)) & 0x0C30C30C30C3ull;
  v = (v | (v << 2)) & 0x249249249249ull;
  return v;
}

/// Gathers every third bit of v (bit 3i goes to bit i): spreadBits3's inverse.
inline std::uint64_t compactBits3(std::uint64_t v) {
  v &= 0x249249249249ull;
  v = (v | (v >> 2)) & 0x0C30C30C30C3ull;
  v = (v | (v >> 4)) & 0x00F00F00F00Full;
  v = (v | (v >> 8)) & 0x0000FF0000FFull;
  v = (v | (v >> 16)) & 0xFFFFull;
  return v;
}

inline std::uint64_t mortonCode(const octomap::OcTreeKey& k) {
  return spreadBits3(k[0]) | (spreadBits3(k[1]) << 1) | (spreadBits3(k[2]) << 2);
}

/// The key of a Morton code (mortonCode's inverse).
inline octomap::OcTreeKey keyOfMortonCode(std::uint64_t code) {
  return octomap::OcTreeKey(static_cast<octomap::key_type>(compactBits3(code)),
                            static_cast<octomap::key_type>(compactBits3(code >> 1)),
                            static_cast<octomap::key_type>(compactBits3(code >> 2)));
}

}  // namespace rgbdi::mapping::detail
