#include "mapping/cell_blocks.h"

namespace rgbdi::mapping::detail {
namespace {

constexpr int kBlockCoordMax = 8191;  // 32768 cells per axis / 4

// Cells of a block on one face, per axis (bit = x + 4 y + 16 z).
constexpr std::uint64_t kLow[3] = {0x1111111111111111ull, 0x000F000F000F000Full,
                                   0x000000000000FFFFull};
constexpr std::uint64_t kHigh[3] = {0x8888888888888888ull, 0xF000F000F000F000ull,
                                    0xFFFF000000000000ull};
constexpr int kStride[3] = {1, 4, 16};

/// Dilates `m` by one cell along `axis`: out[0] lands in the block below, out[1] in the same
/// block, out[2] in the block above.
void dilate(std::uint64_t m, int axis, std::uint64_t out[3]) {
  const int s = kStride[axis];
  out[0] = (m & kLow[axis]) << (3 * s);  // coordinate 0 -> coordinate 3 of the block below
  out[1] = m | ((m & ~kHigh[axis]) << s) | ((m & ~kLow[axis]) >> s);
  out[2] = (m & kHigh[axis]) >> (3 * s);  // coordinate 3 -> coordinate 0 of the block above
}

}  // namespace

std::uint32_t CellBlocks::findBlock(int bx, int by, int bz) const {
  if (bx < 0 || by < 0 || bz < 0 || bx > kBlockCoordMax || by > kBlockCoordMax ||
      bz > kBlockCoordMax)
    return kNoBlock;
  const std::uint32_t* b = index_.find(blockKey(bx, by, bz));
  return b ? *b : kNoBlock;
}

std::uint32_t CellBlocks::findOrAddBlock(int bx, int by, int bz) {
  const std::uint64_t key = blockKey(bx, by, bz);
  if (const std::uint32_t* cached = cache_.find(key)) return *cached;
  bool added = false;
  const std::uint32_t b =
      index_.findOrInsert(key, static_cast<std::uint32_t>(blocks_.size()), added);
  if (added) {
    blocks_.emplaceBack();
    blocks_.back().key = key;
  }
  cache_.put(key, b);
  return b;
}

void CellBlocks::add(const CellCoord& c, std::int64_t delta) {
  const std::uint32_t b = findOrAddBlock(c.x >> 2, c.y >> 2, c.z >> 2);
  Block& block = blocks_[b];
  const int bit = (c.x & 3) + 4 * (c.y & 3) + 16 * (c.z & 3);
  block.count[bit] =
      static_cast<std::uint32_t>(static_cast<std::int64_t>(block.count[bit]) + delta);
  if (block.changed == 0) changed_blocks_.push_back(b);
  block.changed |= std::uint64_t{1} << bit;
}

std::uint32_t CellBlocks::count(const CellCoord& c) const {
  const std::uint32_t b = findBlock(c.x >> 2, c.y >> 2, c.z >> 2);
  if (b == kNoBlock) return 0;
  return blocks_[b].count[(c.x & 3) + 4 * (c.y & 3) + 16 * (c.z & 3)];
}

std::vector<CellCoord> CellBlocks::takeIsolatedCells(std::uint32_t min_count) {
  // 1. Dilate the changed cells of each block into the evaluation masks of the block and its
  // 26 neighbours (absent neighbours hold no points: nothing to evaluate there).
  std::vector<std::uint32_t> to_evaluate;
  for (std::uint32_t b : changed_blocks_) {
    const std::uint64_t changed = blocks_[b].changed;
    blocks_[b].changed = 0;
    const int bx = static_cast<int>(blocks_[b].key >> 32);
    const int by = static_cast<int>((blocks_[b].key >> 16) & 0xffff);
    const int bz = static_cast<int>(blocks_[b].key & 0xffff);
    std::uint64_t along_x[3];
    dilate(changed, 0, along_x);
    for (int ix = 0; ix < 3; ++ix) {
      if (along_x[ix] == 0) continue;
      std::uint64_t along_y[3];
      dilate(along_x[ix], 1, along_y);
      for (int iy = 0; iy < 3; ++iy) {
        if (along_y[iy] == 0) continue;
        std::uint64_t along_z[3];
        dilate(along_y[iy], 2, along_z);
        for (int iz = 0; iz < 3; ++iz) {
          if (along_z[iz] == 0) continue;
          const std::uint32_t nb =
              ix == 1 && iy == 1 && iz == 1 ? b : findBlock(bx + ix - 1, by + iy - 1, bz + iz - 1);
          if (nb == kNoBlock) continue;
          if (blocks_[nb].evaluate == 0) to_evaluate.push_back(nb);
          blocks_[nb].evaluate |= along_z[iz];
        }
      }
    }
  }
  changed_blocks_.clear();

  // 2. Evaluate the marked cells that hold points: their own count first (usually enough), then
  // the neighbours, through the 27 blocks around (looked up once per block, when needed).
  std::vector<CellCoord> isolated;
  for (std::uint32_t b : to_evaluate) {
    Block& block = blocks_[b];
    std::uint64_t todo = block.evaluate;
    block.evaluate = 0;
    const int bx = static_cast<int>(block.key >> 32);
    const int by = static_cast<int>((block.key >> 16) & 0xffff);
    const int bz = static_cast<int>(block.key & 0xffff);
    std::array<const Block*, 27> around{};
    bool around_known = false;
    for (; todo != 0; todo &= todo - 1) {
      const int bit = __builtin_ctzll(todo);
      std::uint32_t n = block.count[bit];
      if (n == 0 || n >= min_count) continue;
      if (!around_known) {
        for (int i = 0; i < 27; ++i) {
          const std::uint32_t nb =
              i == 13 ? b : findBlock(bx + i % 3 - 1, by + (i / 3) % 3 - 1, bz + i / 9 - 1);
          around[static_cast<std::size_t>(i)] = nb == kNoBlock ? nullptr : &blocks_[nb];
        }
        around_known = true;
      }
      const int lx = bit & 3, ly = (bit >> 2) & 3, lz = bit >> 4;
      for (int dz = -1; dz <= 1 && n < min_count; ++dz)
        for (int dy = -1; dy <= 1 && n < min_count; ++dy)
          for (int dx = -1; dx <= 1 && n < min_count; ++dx) {
            if (dx == 0 && dy == 0 && dz == 0) continue;
            const int x = lx + dx, y = ly + dy, z = lz + dz;
            const int i = (x < 0   ? 0
                           : x > 3 ? 2
                                   : 1) +
                          3 * (y < 0   ? 0
                               : y > 3 ? 2
                                       : 1) +
                          9 * (z < 0   ? 0
                               : z > 3 ? 2
                                       : 1);
            const Block* nb = around[static_cast<std::size_t>(i)];
            if (nb != nullptr) n += nb->count[(x & 3) + 4 * (y & 3) + 16 * (z & 3)];
          }
      if (n < min_count) isolated.push_back({4 * bx + lx, 4 * by + ly, 4 * bz + lz});
    }
  }
  return isolated;
}

void CellBlocks::discardChanges() {
  for (std::uint32_t b : changed_blocks_) blocks_[b].changed = 0;
  changed_blocks_.clear();
}

void CellBlocks::clear() {
  cache_.clear();
  index_.clear();
  blocks_.clear();
  changed_blocks_.clear();
}

std::size_t CellBlocks::bytes() const {
  return index_.bytes() + blocks_.bytes() + changed_blocks_.capacity() * sizeof(std::uint32_t);
}

}  // namespace rgbdi::mapping::detail
