#include "navmap/layer_reuse.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rgbdi::navmap::detail {

bool latticeShift(const GridGeometry& grid, const GridGeometry& old_grid, LatticeShift* shift) {
  std::int64_t kx = 0, ky = 0, okx = 0, oky = 0;
  if (grid.cell_size_m != old_grid.cell_size_m || !grid.latticeOrigin(&kx, &ky) ||
      !old_grid.latticeOrigin(&okx, &oky))
    return false;
  shift->dx = kx - okx;
  shift->dy = ky - oky;
  shift->old_width = old_grid.width;
  shift->old_height = old_grid.height;
  return true;
}

std::vector<std::uint8_t> cellsToRecompute(const GridGeometry& grid, const std::vector<float>& now,
                                           const LatticeShift& shift, const std::vector<float>& old,
                                           int r) {
  std::vector<std::uint8_t> out(grid.cellCount(), 0);
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::size_t i = grid.index(ix, iy);
      if (ix < r || iy < r || ix >= grid.width - r || iy >= grid.height - r) out[i] = 1;
      const std::int64_t j = shift.oldIndex(ix, iy);
      const float was = j >= 0 ? old[static_cast<std::size_t>(j)] : NAN;
      const bool same =
          std::isnan(was) ? std::isnan(now[i]) : std::memcmp(&was, &now[i], sizeof(float)) == 0;
      if (same) continue;
      for (int y = std::max(0, iy - r); y <= std::min(grid.height - 1, iy + r); ++y)
        std::fill_n(out.begin() + static_cast<std::ptrdiff_t>(grid.index(std::max(0, ix - r), y)),
                    std::min(grid.width - 1, ix + r) - std::max(0, ix - r) + 1, 1);
    }
  return out;
}

}  // namespace rgbdi::navmap::detail
