// A 2-D gravity-aligned plan of the world built from depth: each cell of the x-y plane counts
// the surface samples that fell in it within a height band around the camera (walls,
// furniture: "hits") and the rays that crossed it within that band ("misses"), and keeps the
// height of the floor seen in it (samples below the band). Occupied / free / unknown follow
// from the counts. Both the saved map (all its keyframes) and a run's local submap (its latest
// keyframes, in the odometry frame) become one; ScanSearch fits the second into the first.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rgbdi/reloc/reloc_options.h"

namespace rgbdi::reloc {

/// One depth sample: the camera centre that saw it and the surface point, in one frame (z up).
struct DepthSample {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
};

enum class CellState : std::uint8_t { kUnknown, kFree, kOccupied };

class PlanGrid {
 public:
  PlanGrid() = default;
  /// The plan of `samples`: the grid covers every origin and every used point (cells aligned
  /// to multiples of the resolution: cell (i, j) spans [x0 + i r, x0 + (i + 1) r), x0 = r *
  /// floor(min x / r)). Samples farther than max_range_m from their origin are left out.
  static PlanGrid build(const std::vector<DepthSample>& samples, const PlanGridOptions& options);

  int width() const { return width_; }
  int height() const { return height_; }
  double resolution() const { return resolution_; }
  /// [m] x, y of the lower corner of cell (0, 0).
  const Eigen::Vector2d& corner() const { return corner_; }
  bool inside(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width_ && iy < height_; }
  /// Cell holding x, y (may be outside the grid).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& xy) const;
  Eigen::Vector2d centre(int ix, int iy) const;
  /// kUnknown outside the grid.
  CellState state(int ix, int iy) const;
  int hits(int ix, int iy) const { return hits_[index(ix, iy)]; }
  int misses(int ix, int iy) const { return misses_[index(ix, iy)]; }
  /// [m] mean height of the floor samples of the cell; false when it has none.
  bool floorHeight(int ix, int iy, double* z) const;
  /// Free, and no occupied cell among its 8 neighbours: free space a one-cell misalignment
  /// cannot explain away.
  bool freeInterior(int ix, int iy) const;
  std::vector<Eigen::Vector2i> cells(CellState s) const;
  std::size_t count(CellState s) const;

 private:
  std::size_t index(int ix, int iy) const {
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(ix);
  }
  int width_ = 0, height_ = 0;
  double resolution_ = 0.05;
  int min_hits_ = 1;
  Eigen::Vector2d corner_ = Eigen::Vector2d::Zero();
  std::vector<std::int32_t> hits_, misses_, floor_n_;
  std::vector<double> floor_sum_;
};

}  // namespace rgbdi::reloc
