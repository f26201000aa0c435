// Leaf key -> leaf record, in blocks of 4 x 4 x 4 leaves (8 cm at 2 cm): a hash table finds
// the block, a 64-entry array inside it the leaf. The points of one keyframe arrive in image
// order, so consecutive look-ups mostly fall in the block of the previous one, which is cached:
// no hash probe and no cache miss for them. A flat hash of every leaf made each look-up a
// cache miss into a table of 2-4 slots per leaf (the largest cost of inserting and of the map
// update after a loop, measured with perf). Blocks stay allocated until clear(): a block whose
// leaves all went costs 256 bytes. Internal to the mapping stage.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/key_index_table.h"

namespace rgbdi::mapping::detail {

class LeafIndex {
 public:
  static constexpr std::uint32_t kAbsent = ~std::uint32_t{0};

  /// The value of the packed leaf key (16 bits per axis, x highest), or kAbsent.
  std::uint32_t find(std::uint64_t key) const {
    const std::uint64_t b = blockOf(key);
    const std::uint32_t block = b == cached_key_ ? cached_block_ : lookup(b);
    return block == kAbsent ? kAbsent : blocks_[block][localOf(key)];
  }
  /// The value of `key`, set to `value` first when the key is absent (`added` says which).
  std::uint32_t findOrInsert(std::uint64_t key, std::uint32_t value, bool& added) {
    std::uint32_t& slot = slotOf(key);
    added = slot == kAbsent;
    if (added) slot = value;
    return slot;
  }
  /// Sets the value of a key (present or not).
  void set(std::uint64_t key, std::uint32_t value) { slotOf(key) = value; }
  void erase(std::uint64_t key) { slotOf(key) = kAbsent; }

  void clear() {
    table_.clear();
    blocks_.clear();
    cached_key_ = KeyIndexTable::kEmpty;
  }
  std::size_t bytes() const {
    return table_.bytes() + blocks_.capacity() * sizeof(std::array<std::uint32_t, 64>);
  }

 private:
  static std::uint64_t blockOf(std::uint64_t key) {
    const std::uint64_t x = (key >> 32) & 0xffff, y = (key >> 16) & 0xffff, z = key & 0xffff;
    return ((x >> 2) << 32) | ((y >> 2) << 16) | (z >> 2);
  }
  static std::size_t localOf(std::uint64_t key) {
    return static_cast<std::size_t>(((key >> 32) & 3) | (((key >> 16) & 3) << 2) |
                                    ((key & 3) << 4));
  }
  std::uint32_t lookup(std::uint64_t block_key) const {
    const std::uint32_t* b = table_.find(block_key);
    return b == nullptr ? kAbsent : *b;
  }
  std::uint32_t& slotOf(std::uint64_t key) {
    const std::uint64_t b = blockOf(key);
    if (b != cached_key_) {
      bool added = false;
      cached_block_ = table_.findOrInsert(b, static_cast<std::uint32_t>(blocks_.size()), added);
      if (added) {
        blocks_.emplace_back();
        blocks_.back().fill(kAbsent);
      }
      cached_key_ = b;
    }
    return blocks_[cached_block_][localOf(key)];
  }

  KeyIndexTable table_;
  std::vector<std::array<std::uint32_t, 64>> blocks_;
  // The block of the last insertion or change (const look-ups read it, never write it).
  std::uint64_t cached_key_ = KeyIndexTable::kEmpty;
  std::uint32_t cached_block_ = 0;
};

}  // namespace rgbdi::mapping::detail
