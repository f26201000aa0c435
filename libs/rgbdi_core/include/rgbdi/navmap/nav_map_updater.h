// Incremental navigation maps (doc/navigation-maps.md "Incremental update"): the map's points
// are kept binned per cell of the lattice of cell_size_m cells (the cells of every grid
// buildNavMap places), each cell with its heights sorted and what they say about it (lowest
// surface, obstacle band). Adding a keyframe's points inserts them into their cells and
// re-derives only those cells; build() then derives the layers that depend on the path (ground
// under the path, overhangs, slopes, steps, plateaus, traversability) over the path's grid. The
// result equals buildNavMap() from all the points added, in any order and split (same cells,
// same sorted heights, same stage 2). A loop correction moves the points: clear() and add them
// again.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/navmap/navmap_options.h"

namespace rgbdi::navmap {
namespace detail {
struct LayerCache;
}

class NavMapUpdater {
 public:
  /// Throws ConfigError naming the key for invalid options.
  explicit NavMapUpdater(const NavMapOptions& options);
  ~NavMapUpdater();
  NavMapUpdater(NavMapUpdater&&) noexcept;
  NavMapUpdater& operator=(NavMapUpdater&&) noexcept;

  /// Adds map points (map frame, z up); points with a non-finite coordinate are ignored.
  void addPoints(const std::vector<Eigen::Vector3f>& points);
  /// Forgets every point (before the points are added again after their poses moved).
  void clear();

  std::size_t pointCount() const { return points_; }
  /// Cells holding at least one point.
  std::size_t occupiedCells() const { return cells_; }

  /// The layers for this path: buildNavMap(every point added, path, options). Throws
  /// std::invalid_argument for an empty path.
  NavMap build(const std::vector<Eigen::Vector3d>& path);

 private:
  struct Cell {
    std::vector<float> z;  ///< heights [m], ascending
    float ground_z_m = 0.0f;
    float sigma_m = 0.0f;
    float rise_m = 0.0f;  ///< [m] CellSurface::rise_m
    bool obstacle = false;
    bool touched = false;  ///< points added since the cell was last derived
  };
  static constexpr int kTileBits = 6;  ///< tiles of 64 x 64 cells
  static constexpr int kTileSide = 1 << kTileBits;
  struct Tile {
    std::vector<Cell> cells = std::vector<Cell>(kTileSide * kTileSide);
  };

  NavMapOptions options_;
  std::unordered_map<std::uint64_t, Tile> tiles_;  ///< by packed tile coordinates
  std::size_t points_ = 0;
  std::size_t cells_ = 0;
  std::unique_ptr<detail::LayerCache> cache_;  ///< the previous build's window layers
};

}  // namespace rgbdi::navmap
