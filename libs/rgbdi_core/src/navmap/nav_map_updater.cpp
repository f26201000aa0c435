#include "rgbdi/navmap/nav_map_updater.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "navmap/nav_map_stages.h"

namespace rgbdi::navmap {
namespace {

std::uint64_t tileKey(std::int64_t tx, std::int64_t ty) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(tx)) << 32) |
         static_cast<std::uint32_t>(ty);
}
std::int64_t tileX(std::uint64_t key) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(key >> 32));
}
std::int64_t tileY(std::uint64_t key) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(key & 0xffffffffu));
}

}  // namespace

NavMapUpdater::NavMapUpdater(const NavMapOptions& options)
    : options_(options), cache_(std::make_unique<detail::LayerCache>()) {
  options_.validate();
}
NavMapUpdater::~NavMapUpdater() = default;
NavMapUpdater::NavMapUpdater(NavMapUpdater&&) noexcept = default;
NavMapUpdater& NavMapUpdater::operator=(NavMapUpdater&&) noexcept = default;

void NavMapUpdater::clear() {
  tiles_.clear();
  points_ = 0;
  cells_ = 0;
}

void NavMapUpdater::addPoints(const std::vector<Eigen::Vector3f>& points) {
  const double c = options_.cell_size_m;
  // Tile coordinates are 32-bit: beyond +-2^37 cells (7e9 km at 5 cm) a point is ignored.
  constexpr std::int64_t kMaxCell = std::int64_t{1} << 37;
  std::vector<Cell*> touched;
  std::uint64_t last_key = 0;
  Tile* last_tile = nullptr;
  for (const Eigen::Vector3f& p : points) {
    std::int64_t kx = 0, ky = 0;
    if (!std::isfinite(p.z()) || !latticeCell(p.x(), c, &kx) || !latticeCell(p.y(), c, &ky) ||
        std::abs(kx) >= kMaxCell || std::abs(ky) >= kMaxCell)
      continue;
    // Arithmetic shift: floor division by the tile side, also for negative cells.
    const std::uint64_t key = tileKey(kx >> kTileBits, ky >> kTileBits);
    if (last_tile == nullptr || key != last_key) {
      last_tile = &tiles_[key];
      last_key = key;
    }
    Cell& cell = last_tile->cells[static_cast<std::size_t>((ky & (kTileSide - 1)) * kTileSide +
                                                           (kx & (kTileSide - 1)))];
    if (cell.z.empty()) ++cells_;
    cell.z.insert(std::upper_bound(cell.z.begin(), cell.z.end(), p.z()), p.z());
    ++points_;
    if (!cell.touched) {
      cell.touched = true;
      touched.push_back(&cell);
    }
  }
  // Only the cells that received points are derived again.
  for (Cell* cell : touched) {
    const detail::CellSurface s =
        detail::cellSurface(cell->z.data(), cell->z.data() + cell->z.size(), options_);
    cell->ground_z_m = s.ground_z_m;
    cell->sigma_m = s.sigma_m;
    cell->obstacle = s.obstacle;
    cell->rise_m = s.rise_m;
    cell->touched = false;
  }
}

NavMap NavMapUpdater::build(const std::vector<Eigen::Vector3d>& path) {
  if (path.empty()) throw std::invalid_argument("navmap: empty path");
  const GridGeometry grid = gridAroundPath(path, options_);
  std::int64_t kx0 = 0, ky0 = 0;
  if (!grid.latticeOrigin(&kx0, &ky0))
    throw std::logic_error("navmap: the path's grid is not on the lattice of cells");
  detail::NearestPose near;
  NavMap m = detail::startNavMap(path, options_, grid, &near);
  std::vector<std::uint8_t> obstacle(grid.cellCount(), 0);
  std::vector<float> rise(grid.cellCount(), 0.0f);
  for (const auto& [key, tile] : tiles_) {
    const std::int64_t cx = tileX(key) * kTileSide - kx0, cy = tileY(key) * kTileSide - ky0;
    if (cx >= grid.width || cy >= grid.height || cx + kTileSide <= 0 || cy + kTileSide <= 0)
      continue;
    for (int ty = 0; ty < kTileSide; ++ty) {
      const std::int64_t iy = cy + ty;
      if (iy < 0 || iy >= grid.height) continue;
      for (int tx = 0; tx < kTileSide; ++tx) {
        const std::int64_t ix = cx + tx;
        if (ix < 0 || ix >= grid.width) continue;
        const Cell& cell = tile.cells[static_cast<std::size_t>(ty * kTileSide + tx)];
        const std::size_t i = grid.index(static_cast<int>(ix), static_cast<int>(iy));
        if (cell.z.empty() || !(near.distance_m[i] <= options_.range_m)) continue;
        m.ground_z_m[i] = cell.ground_z_m;
        m.ground_sigma_m[i] = cell.sigma_m;
        obstacle[i] = cell.obstacle ? 1 : 0;
        rise[i] = cell.rise_m;
      }
    }
  }
  detail::finishNavMap(m, near, obstacle, rise, path, options_, cache_.get());
  return m;
}

}  // namespace rgbdi::navmap
