// The map's points binned per grid cell: the heights of each cell's points, sorted, in one
// array (counting sort by cell), so that a cell's lowest surface and the points above it are
// found by binary search. A grid whose origin is on the lattice of cells (GridGeometry::
// latticeOrigin, every grid buildNavMap places) bins by latticeCell, as NavMapUpdater does.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rgbdi/navmap/grid_geometry.h"

namespace rgbdi::navmap::detail {

class CellPoints {
 public:
  CellPoints(const std::vector<Eigen::Vector3f>& points, const GridGeometry& grid);

  /// Heights [m] of the points in cell i, ascending.
  const float* begin(std::size_t i) const { return z_.data() + start_[i]; }
  const float* end(std::size_t i) const { return z_.data() + start_[i + 1]; }
  std::size_t size(std::size_t i) const { return start_[i + 1] - start_[i]; }

 private:
  std::vector<std::uint32_t> start_;  ///< cellCount + 1 offsets into z_
  std::vector<float> z_;
};

/// The cell of `grid` (origin at lattice cell (kx0, ky0)) holding p by lattice binning; false
/// outside the grid or for a non-finite x or y.
bool latticeCellOf(const Eigen::Vector3f& p, const GridGeometry& grid, std::int64_t kx0,
                   std::int64_t ky0, int* ix, int* iy);

/// The lowest surface of a cell: mean and standard deviation of the points within band of its
/// k-th lowest point; false when fewer than k points are there.
bool lowestSurface(const float* first, const float* last, int k, float band, float* mean,
                   float* sigma);

}  // namespace rgbdi::navmap::detail
