// Reuse of a previous build's window layers (NavMapUpdater): a cell's plane fit depends only on
// the ground of the cells within the footprint around it, its traversability only on the scores
// there. Where none of those inputs changed since the previous build (same lattice cell, same
// bits) the previous output is the output; only the cells near a change are computed again.
#pragma once

#include <cstdint>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"

namespace rgbdi::navmap::detail {

/// The inputs and outputs of the previous build's window layers, on its grid.
struct LayerCache {
  bool valid = false;
  GridGeometry grid;
  std::vector<float> plane_ground;  ///< input of the plane fits
  std::vector<float> slope_deg, roughness_m;
  std::vector<float> score;  ///< input of the traversability
  std::vector<float> traversability;
};

/// Where `grid` and `old_grid` are both on the lattice (same cell size): the offset of the old
/// grid's cell for a cell of `grid`; false otherwise (nothing can be reused).
struct LatticeShift {
  std::int64_t dx = 0, dy = 0;
  int old_width = 0, old_height = 0;
  /// Index in the old grid of cell (ix, iy) of the new one, -1 outside the old grid.
  std::int64_t oldIndex(int ix, int iy) const {
    const std::int64_t ox = ix + dx, oy = iy + dy;
    if (ox < 0 || oy < 0 || ox >= old_width || oy >= old_height) return -1;
    return oy * old_width + ox;
  }
};
bool latticeShift(const GridGeometry& grid, const GridGeometry& old_grid, LatticeShift* shift);

/// 1 for the cells of `grid` to compute again: those with a cell within r (square window) whose
/// value in `now` differs from `old` at the same lattice cell (NaN outside the old grid), and
/// those within r of the grid's border (their window reaches beyond it).
std::vector<std::uint8_t> cellsToRecompute(const GridGeometry& grid, const std::vector<float>& now,
                                           const LatticeShift& shift, const std::vector<float>& old,
                                           int r);

}  // namespace rgbdi::navmap::detail
