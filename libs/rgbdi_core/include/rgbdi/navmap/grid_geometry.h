// Placement of a 2-D grid in the gravity-aligned map frame (x, y horizontal, z up): cell (ix, iy)
// covers [origin_x + ix * cell, origin_x + (ix + 1) * cell) x [origin_y + iy * cell, ...).
// Cells are stored row by row from iy = 0 (lowest y), as MRPT and ROS index them.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace rgbdi::navmap {

/// The lattice cell holding coordinate v [m] (cells of side c at multiples of c): the binning of
/// map points shared by every grid on the lattice, so that a point falls in the same cell
/// whatever the grid's extent (full build and incremental update agree exactly). false when v
/// is not finite or too far out.
inline bool latticeCell(double v, double c, std::int64_t* k) {
  const double f = std::floor(v / c);
  if (!(std::abs(f) < 1e15)) return false;  // also NaN and infinities
  *k = static_cast<std::int64_t>(f);
  return true;
}

struct GridGeometry {
  double origin_x_m = 0.0;  ///< [m] x of the outer corner of cell (0, 0)
  double origin_y_m = 0.0;  ///< [m] y of that corner
  double cell_size_m = 0.05;
  int width = 0;   ///< cells along x
  int height = 0;  ///< cells along y

  std::size_t cellCount() const {
    return static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  std::size_t index(int ix, int iy) const {
    return static_cast<std::size_t>(iy) * static_cast<std::size_t>(width) +
           static_cast<std::size_t>(ix);
  }
  bool contains(int ix, int iy) const { return ix >= 0 && iy >= 0 && ix < width && iy < height; }
  /// The cell holding (x, y); false outside the grid.
  bool cellOf(double x, double y, int* ix, int* iy) const {
    const double fx = std::floor((x - origin_x_m) / cell_size_m);
    const double fy = std::floor((y - origin_y_m) / cell_size_m);
    if (!(fx >= 0 && fy >= 0 && fx < width && fy < height)) return false;  // also NaN
    *ix = static_cast<int>(fx);
    *iy = static_cast<int>(fy);
    return true;
  }
  /// Cell indices of the origin on the lattice of cells at multiples of cell_size_m (the grids
  /// buildNavMap places); false when the origin is not on it.
  bool latticeOrigin(std::int64_t* kx, std::int64_t* ky) const {
    const double fx = origin_x_m / cell_size_m, fy = origin_y_m / cell_size_m;
    if (!(std::abs(fx - std::round(fx)) < 1e-6 && std::abs(fy - std::round(fy)) < 1e-6))
      return false;
    *kx = static_cast<std::int64_t>(std::llround(fx));
    *ky = static_cast<std::int64_t>(std::llround(fy));
    return true;
  }
  Eigen::Vector2d centre(int ix, int iy) const {
    return {origin_x_m + (ix + 0.5) * cell_size_m, origin_y_m + (iy + 0.5) * cell_size_m};
  }
};

}  // namespace rgbdi::navmap
