// Point counts of the map's cells (2 x 2 x 2 leaves) in a flat open-addressing hash table, built
// for one pass of the isolated-leaf rule: a neighbour look-up is one or two probes into a
// contiguous array, where a descent of the octree chases a pointer per level.
#pragma once

#include <cstdint>
#include <vector>

namespace rgbdi::mapping::detail {

class CellCountTable {
 public:
  struct Entry {
    std::uint64_t cell = kEmpty;
    std::uint32_t count = 0;
    std::uint8_t evaluated = 0;  ///< the rule was evaluated for this cell in this pass
    std::uint8_t isolated = 0;   ///< ... and its leaves must go
  };
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  /// Room for `cells` distinct cells at a load factor of at most one half.
  explicit CellCountTable(std::size_t cells) {
    std::size_t n = 16;
    int bits = 4;
    for (; n < 2 * cells; n *= 2) ++bits;
    slots_.resize(n);
    mask_ = n - 1;
    shift_ = 64 - bits;
  }

  void add(std::uint64_t cell, std::uint32_t count) { slot(cell).count += count; }

  /// The entry of `cell`, or nullptr when the cell holds no point.
  Entry* find(std::uint64_t cell) {
    for (std::size_t i = hash(cell);; i = (i + 1) & mask_) {
      Entry& e = slots_[i];
      if (e.cell == cell) return &e;
      if (e.cell == kEmpty) return nullptr;
    }
  }

  std::vector<Entry>& slots() { return slots_; }

 private:
  std::size_t hash(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9e3779b97f4a7c15ull) >> shift_);  // Fibonacci hashing
  }
  Entry& slot(std::uint64_t cell) {
    for (std::size_t i = hash(cell);; i = (i + 1) & mask_) {
      Entry& e = slots_[i];
      if (e.cell == cell) return e;
      if (e.cell == kEmpty) {
        e.cell = cell;
        return e;
      }
    }
  }

  std::vector<Entry> slots_;
  std::size_t mask_ = 0;
  int shift_ = 60;
};

}  // namespace rgbdi::mapping::detail
