// Point counts of the map's cells (a cell is 2 x 2 x 2 leaves), stored in blocks of 4 x 4 x 4
// cells found through a hash table, with per-block bit masks of the cells whose count changed
// since the isolated-leaf rule last ran. The rule needs, around every changed cell, the counts of
// the 27 cells of each neighbour: in blocks they are mostly in the same 256-byte array, and a
// changed region is dilated with a few shifts of 64-bit masks instead of 27 hash probes per cell
// (a flat per-cell hash table made the rule's look-ups cache misses: the largest cost of the map
// update after a loop). Internal to the mapping stage.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/chunked_vector.h"
#include "mapping/key_index_table.h"

namespace rgbdi::mapping::detail {

/// Cell coordinates: the leaf's OctoMap key halved (0 .. 32767 per axis).
struct CellCoord {
  int x = 0, y = 0, z = 0;
};

class CellBlocks {
 public:
  /// Adds `delta` to the cell's count (never below zero by use) and marks the cell changed.
  void add(const CellCoord& c, std::int64_t delta);
  /// The cell's count (0 when unknown).
  std::uint32_t count(const CellCoord& c) const;

  /// The isolated-leaf rule where it can have changed: every cell holding points within one
  /// cell of a changed cell is evaluated once, on the counts as they are now: it is isolated
  /// when its 3 x 3 x 3 neighbourhood holds fewer than `min_count` points. Returns the isolated
  /// cells (in a deterministic order) and clears the changed marks.
  std::vector<CellCoord> takeIsolatedCells(std::uint32_t min_count);
  /// Clears the changed marks without evaluating anything.
  void discardChanges();

  void clear();
  std::size_t blockCount() const { return blocks_.size(); }
  std::size_t bytes() const;

 private:
  struct Block {
    std::uint64_t key = 0;
    std::uint64_t changed = 0;              ///< cells whose count changed since the rule last ran
    std::uint64_t evaluate = 0;             ///< cells to evaluate in the current pass
    std::array<std::uint32_t, 64> count{};  ///< bit/index = x + 4 y + 16 z (local coordinates)
  };
  static std::uint64_t blockKey(int bx, int by, int bz) {
    return (static_cast<std::uint64_t>(bx) << 32) | (static_cast<std::uint64_t>(by) << 16) |
           static_cast<std::uint64_t>(bz);
  }
  /// Index of the block at block coordinates, or kNoBlock (also beyond the key range).
  std::uint32_t findBlock(int bx, int by, int bz) const;
  std::uint32_t findOrAddBlock(int bx, int by, int bz);

  static constexpr std::uint32_t kNoBlock = ~std::uint32_t{0};
  KeyIndexTable index_;
  ChunkedVector<Block, 256> blocks_;
  std::vector<std::uint32_t> changed_blocks_;  ///< blocks with changed != 0
  // Blocks of recent add() calls: a keyframe's points arrive in image order, mostly in a
  // block used a moment ago.
  BlockCache cache_;
};

}  // namespace rgbdi::mapping::detail
