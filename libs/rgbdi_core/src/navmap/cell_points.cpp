#include "navmap/cell_points.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rgbdi::navmap::detail {

CellPoints::CellPoints(const std::vector<Eigen::Vector3f>& points, const GridGeometry& grid) {
  if (points.size() >= 0xffffffffu)
    throw std::invalid_argument("navmap: more than 4 billion points");
  const std::size_t n_cells = grid.cellCount();
  std::vector<std::uint32_t> cell(points.size(), 0xffffffffu);
  start_.assign(n_cells + 1, 0);
  std::int64_t kx0 = 0, ky0 = 0;
  const bool lattice = grid.latticeOrigin(&kx0, &ky0);
  for (std::size_t p = 0; p < points.size(); ++p) {
    int ix = 0, iy = 0;
    if (!std::isfinite(points[p].z())) continue;
    if (lattice) {
      if (!latticeCellOf(points[p], grid, kx0, ky0, &ix, &iy)) continue;
    } else if (!grid.cellOf(points[p].x(), points[p].y(), &ix, &iy)) {
      continue;
    }
    cell[p] = static_cast<std::uint32_t>(grid.index(ix, iy));
    ++start_[cell[p] + 1];
  }
  for (std::size_t i = 0; i < n_cells; ++i) start_[i + 1] += start_[i];
  z_.resize(start_[n_cells]);
  std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t p = 0; p < points.size(); ++p)
    if (cell[p] != 0xffffffffu) z_[fill[cell[p]]++] = points[p].z();
  // Sorted heights make the result independent of the order of the points.
  for (std::size_t i = 0; i < n_cells; ++i)
    std::sort(z_.begin() + start_[i], z_.begin() + start_[i + 1]);
}

bool latticeCellOf(const Eigen::Vector3f& p, const GridGeometry& grid, std::int64_t kx0,
                   std::int64_t ky0, int* ix, int* iy) {
  std::int64_t kx = 0, ky = 0;
  if (!latticeCell(p.x(), grid.cell_size_m, &kx) || !latticeCell(p.y(), grid.cell_size_m, &ky))
    return false;
  kx -= kx0;
  ky -= ky0;
  if (kx < 0 || ky < 0 || kx >= grid.width || ky >= grid.height) return false;
  *ix = static_cast<int>(kx);
  *iy = static_cast<int>(ky);
  return true;
}

bool lowestSurface(const float* first, const float* last, int k, float band, float* mean,
                   float* sigma) {
  if (last - first < k) return false;
  const float anchor = first[k - 1];
  const float* a = std::lower_bound(first, last, anchor - band);
  const float* b = std::upper_bound(first, last, anchor + band);
  const std::size_t n = static_cast<std::size_t>(b - a);
  double sum = 0.0;
  for (const float* z = a; z != b; ++z) sum += *z;
  const double m = sum / static_cast<double>(n);
  double sq = 0.0;
  for (const float* z = a; z != b; ++z) sq += (*z - m) * (*z - m);
  *mean = static_cast<float>(m);
  *sigma = static_cast<float>(std::sqrt(sq / static_cast<double>(n)));
  return true;
}

}  // namespace rgbdi::navmap::detail
