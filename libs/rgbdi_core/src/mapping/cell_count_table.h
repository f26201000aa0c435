// Point counts of the map's cells (2 x 2 x 2 leaves) in a flat open-addressing hash table, kept
// up to date by every insertion and removal: the isolated-leaf rule then looks a neighbour up in
// one or two probes of a contiguous array (an octree descent chases a pointer per level) and
// needs no pass over the whole map to count.
#pragma once

#include <cstdint>
#include <vector>

namespace rgbdi::mapping::detail {

class CellCountTable {
 public:
  struct Entry {
    std::uint64_t cell = kEmpty;
    std::uint32_t count = 0;  ///< 0: the cell holds no point (the slot stays until a rehash)
    std::uint32_t stamp = 0;  ///< pass of the isolated-leaf rule that last evaluated the cell
  };
  static constexpr std::uint64_t kEmpty = ~std::uint64_t{0};

  CellCountTable() { reset(16); }

  void clear() { reset(16); }

  /// Adds `delta` (may be negative; the count never goes below zero by use) to the cell's count.
  void add(std::uint64_t cell, std::int64_t delta) {
    Entry& e = slot(cell);
    e.count = static_cast<std::uint32_t>(static_cast<std::int64_t>(e.count) + delta);
  }

  /// The entry of `cell`, or nullptr when the cell holds no point.
  Entry* find(std::uint64_t cell) {
    for (std::size_t i = hash(cell);; i = (i + 1) & mask_) {
      Entry& e = slots_[i];
      if (e.cell == cell) return e.count > 0 ? &e : nullptr;
      if (e.cell == kEmpty) return nullptr;
    }
  }

  std::vector<Entry>& slots() { return slots_; }
  std::size_t bytes() const { return slots_.capacity() * sizeof(Entry); }

 private:
  void reset(std::size_t n) {
    slots_.assign(n, Entry{});
    mask_ = n - 1;
    shift_ = 64;
    for (std::size_t s = n; s > 1; s >>= 1) --shift_;
    used_ = 0;
  }
  std::size_t hash(std::uint64_t k) const {
    return static_cast<std::size_t>((k * 0x9e3779b97f4a7c15ull) >> shift_);  // Fibonacci hashing
  }
  Entry& slot(std::uint64_t cell) {
    for (std::size_t i = hash(cell);; i = (i + 1) & mask_) {
      Entry& e = slots_[i];
      if (e.cell == cell) return e;
      if (e.cell == kEmpty) {
        if (2 * (used_ + 1) > slots_.size()) {  // keep the load under one half
          grow();
          return slot(cell);
        }
        ++used_;
        e.cell = cell;
        return e;
      }
    }
  }
  /// Rehashes without the cells that hold no point any more.
  void grow() {
    std::vector<Entry> old;
    old.swap(slots_);
    std::size_t live = 0;
    for (const Entry& e : old) live += e.cell != kEmpty && e.count > 0;
    std::size_t n = 16;
    while (n < 4 * (live + 1)) n *= 2;
    reset(n);
    for (const Entry& e : old)
      if (e.cell != kEmpty && e.count > 0) {
        Entry& d = slot(e.cell);
        d.count = e.count;
        d.stamp = e.stamp;
      }
  }

  std::vector<Entry> slots_;
  std::size_t mask_ = 0, used_ = 0;
  int shift_ = 60;
};

}  // namespace rgbdi::mapping::detail
