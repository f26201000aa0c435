// A flat open-addressing hash table from 64-bit keys to 32-bit indices (linear probing, load
// kept under one half, insert-only: the point map's blocks live until the map is cleared), and
// a small direct-mapped cache in front of it. The point map finds its leaf and cell blocks by
// packed block coordinates through them. Internal to the mapping stage.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rgbdi::mapping::detail {

class KeyIndexTable {
 public:
  /// Reserved: never a key of the table.
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  KeyIndexTable() { reset(16); }

  void clear() { reset(16); }
  std::size_t size() const { return used_; }
  std::size_t bytes() const {
    return keys_.capacity() * sizeof(std::uint64_t) + values_.capacity() * sizeof(std::uint32_t);
  }

  /// The value of `key`, or nullptr.
  std::uint32_t* find(std::uint64_t key) {
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  const std::uint32_t* find(std::uint64_t key) const {
    return const_cast<KeyIndexTable*>(this)->find(key);
  }

  /// The value of `key`, inserting `value` when the key is absent; `added` says which.
  std::uint32_t& findOrInsert(std::uint64_t key, std::uint32_t value, bool& added) {
    for (std::size_t i = home(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) {
        added = false;
        return values_[i];
      }
      if (keys_[i] == kEmpty) {
        if (2 * (used_ + 1) > keys_.size()) {
          grow();
          return findOrInsert(key, value, added);
        }
        ++used_;
        keys_[i] = key;
        values_[i] = value;
        added = true;
        return values_[i];
      }
    }
  }

 private:
  void reset(std::size_t n) {
    keys_.assign(n, kEmpty);
    values_.assign(n, 0);
    mask_ = n - 1;
    shift_ = 64;
    for (std::size_t s = n; s > 1; s >>= 1) --shift_;
    used_ = 0;
  }
  std::size_t home(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9e3779b97f4a7c15ull) >> shift_);  // Fibonacci hashing
  }
  void grow() {
    std::vector<std::uint64_t> old_keys;
    std::vector<std::uint32_t> old_values;
    old_keys.swap(keys_);
    old_values.swap(values_);
    reset(2 * old_keys.size());
    bool added = false;
    for (std::size_t i = 0; i < old_keys.size(); ++i)
      if (old_keys[i] != kEmpty) findOrInsert(old_keys[i], old_values[i], added);
  }

  std::vector<std::uint64_t> keys_;
  std::vector<std::uint32_t> values_;
  std::size_t mask_ = 0, used_ = 0;
  int shift_ = 60;
};

/// A direct-mapped cache of recently used block keys -> block indices in front of a
/// KeyIndexTable, for keys packing three 16-bit block coordinates: the slot is picked by the
/// two low bits of each coordinate, so the blocks around the last few looked up (the next row of
/// a keyframe's image grid lands in them again) are found without touching the table.
class BlockCache {
 public:
  BlockCache() { clear(); }
  void clear() {
    keys_.fill(KeyIndexTable::kEmpty);
    values_.fill(0);
  }
  /// The cached value of `key`, or nullptr.
  const std::uint32_t* find(std::uint64_t key) const {
    const std::size_t s = slot(key);
    return keys_[s] == key ? &values_[s] : nullptr;
  }
  void put(std::uint64_t key, std::uint32_t value) {
    const std::size_t s = slot(key);
    keys_[s] = key;
    values_[s] = value;
  }

 private:
  static std::size_t slot(std::uint64_t key) {
    return static_cast<std::size_t>(((key >> 32) & 3) | (((key >> 16) & 3) << 2) |
                                    ((key & 3) << 4));
  }
  std::array<std::uint64_t, 64> keys_;
  std::array<std::uint32_t, 64> values_;
};

}  // namespace rgbdi::mapping::detail
