// The point map's leaves, in blocks of 4 x 4 x 4 leaves (8 cm at 2 cm) found through a hash
// table of block keys; a block holds the 64 leaf records (point count, first point) in place.
// A leaf's id is block * 64 + position, stable while the map lives, so an emptied leaf costs
// nothing to remove (count 0 = no leaf) and points never need renumbering. The points of one
// keyframe arrive in image order, so most look-ups fall in a block used a moment ago: a small
// direct-mapped cache of blocks (BlockCache) answers them. (A flat hash of every leaf made each
// look-up a cache miss into a table of 2-4 slots per leaf, the largest cost of the map update after
// a loop under perf; an octree descent chases 16 pointers at 2 cm.) Blocks stay allocated until
// clear(): one whose leaves all went costs 520 bytes. Internal to the mapping stage.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/chunked_vector.h"
#include "mapping/key_index_table.h"

namespace rgbdi::mapping::detail {

class LeafBlocks {
 public:
  static constexpr std::uint32_t kNoLeaf = ~std::uint32_t{0};
  struct Leaf {
    std::uint32_t count = 0;       ///< points in the leaf; 0: no leaf
    std::uint32_t head = kNoLeaf;  ///< first point of the leaf's list (kNoLeaf: none)
  };

  /// Id of the leaf at the packed key (16 bits per axis, x highest) if it holds points, else
  /// kNoLeaf.
  std::uint32_t find(std::uint64_t key) const {
    const std::uint64_t b = blockOf(key);
    const std::uint32_t* found = cache_.find(b);
    if (found == nullptr) found = table_.find(b);
    if (found == nullptr) return kNoLeaf;
    const std::uint32_t block = *found;
    const std::uint32_t id = block * 64 + localOf(key);
    return blocks_[block].leaf[localOf(key)].count > 0 ? id : kNoLeaf;
  }
  /// Id of the leaf at the packed key, its block created if needed (the leaf may be empty).
  std::uint32_t touch(std::uint64_t key) {
    const std::uint64_t b = blockOf(key);
    std::uint32_t block = 0;
    if (const std::uint32_t* cached = cache_.find(b)) {
      block = *cached;
    } else {
      bool added = false;
      block = table_.findOrInsert(b, static_cast<std::uint32_t>(blocks_.size()), added);
      if (added) {
        blocks_.emplaceBack();
        blocks_.back().key = b;
      }
      cache_.put(b, block);
    }
    return block * 64 + localOf(key);
  }

  Leaf& operator[](std::uint32_t id) { return blocks_[id >> 6].leaf[id & 63]; }
  const Leaf& operator[](std::uint32_t id) const { return blocks_[id >> 6].leaf[id & 63]; }
  /// Packed key of a leaf id.
  std::uint64_t keyOf(std::uint32_t id) const {
    const std::uint64_t b = blocks_[id >> 6].key;
    const std::uint64_t l = id & 63;
    return ((((b >> 32) << 2) | (l & 3)) << 32) |
           (((((b >> 16) & 0xffff) << 2) | ((l >> 2) & 3)) << 16) |
           (((b & 0xffff) << 2) | (l >> 4));
  }

  void clear() {
    table_.clear();
    blocks_.clear();
    cache_.clear();
  }
  std::size_t blockCount() const { return blocks_.size(); }
  std::size_t bytes() const { return table_.bytes() + blocks_.bytes(); }

 private:
  struct Block {
    std::array<Leaf, 64> leaf;  ///< position = x + 4 y + 16 z (key bits 0-1 of each axis)
    std::uint64_t key = 0;      ///< the leaf key's axes shifted right by 2, packed
  };
  static std::uint64_t blockOf(std::uint64_t key) {
    const std::uint64_t x = (key >> 32) & 0xffff, y = (key >> 16) & 0xffff, z = key & 0xffff;
    return ((x >> 2) << 32) | ((y >> 2) << 16) | (z >> 2);
  }
  static std::uint32_t localOf(std::uint64_t key) {
    return static_cast<std::uint32_t>(((key >> 32) & 3) | (((key >> 16) & 3) << 2) |
                                      ((key & 3) << 4));
  }

  KeyIndexTable table_;
  ChunkedVector<Block, 256> blocks_;
  // Blocks of recent touch() calls (find() reads it, never writes it: const look-ups stay safe).
  BlockCache cache_;
};

}  // namespace rgbdi::mapping::detail
