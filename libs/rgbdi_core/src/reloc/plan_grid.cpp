#include "rgbdi/reloc/plan_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbdi::reloc {
namespace {
bool usable(const DepthSample& s, double max_range) {
  return s.origin.allFinite() && s.point.allFinite() && (s.point - s.origin).norm() <= max_range;
}
}  // namespace

Eigen::Vector2i PlanGrid::cellOf(const Eigen::Vector2d& xy) const {
  return {static_cast<int>(std::floor((xy.x() - corner_.x()) / resolution_)),
          static_cast<int>(std::floor((xy.y() - corner_.y()) / resolution_))};
}

Eigen::Vector2d PlanGrid::centre(int ix, int iy) const {
  return corner_ + resolution_ * Eigen::Vector2d(ix + 0.5, iy + 0.5);
}

CellState PlanGrid::state(int ix, int iy) const {
  if (!inside(ix, iy)) return CellState::kUnknown;
  const std::size_t i = index(ix, iy);
  if (hits_[i] >= min_hits_ && hits_[i] >= misses_[i]) return CellState::kOccupied;
  if (misses_[i] > 0) return CellState::kFree;
  return CellState::kUnknown;
}

bool PlanGrid::floorHeight(int ix, int iy, double* z) const {
  if (!inside(ix, iy)) return false;
  const std::size_t i = index(ix, iy);
  if (floor_n_[i] == 0) return false;
  *z = floor_sum_[i] / floor_n_[i];
  return true;
}

bool PlanGrid::freeInterior(int ix, int iy) const {
  if (state(ix, iy) != CellState::kFree) return false;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (state(ix + dx, iy + dy) == CellState::kOccupied) return false;
  return true;
}

std::vector<Eigen::Vector2i> PlanGrid::cells(CellState s) const {
  std::vector<Eigen::Vector2i> out;
  for (int iy = 0; iy < height_; ++iy)
    for (int ix = 0; ix < width_; ++ix)
      if (state(ix, iy) == s) out.emplace_back(ix, iy);
  return out;
}

std::size_t PlanGrid::count(CellState s) const {
  std::size_t n = 0;
  for (int iy = 0; iy < height_; ++iy)
    for (int ix = 0; ix < width_; ++ix) n += state(ix, iy) == s ? 1 : 0;
  return n;
}

PlanGrid PlanGrid::build(const std::vector<DepthSample>& samples, const PlanGridOptions& o) {
  PlanGrid g;
  g.resolution_ = o.resolution_m;
  g.min_hits_ = o.min_hits;
  const double r = o.resolution_m;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const DepthSample& s : samples) {
    if (!usable(s, o.max_range_m)) continue;
    lo = lo.cwiseMin(s.origin.head<2>()).cwiseMin(s.point.head<2>());
    hi = hi.cwiseMax(s.origin.head<2>()).cwiseMax(s.point.head<2>());
  }
  if (!(lo.x() <= hi.x())) return g;  // nothing usable: an empty plan
  g.corner_ = Eigen::Vector2d(r * std::floor(lo.x() / r), r * std::floor(lo.y() / r));
  g.width_ = static_cast<int>(std::floor((hi.x() - g.corner_.x()) / r)) + 1;
  g.height_ = static_cast<int>(std::floor((hi.y() - g.corner_.y()) / r)) + 1;
  const std::size_t n = static_cast<std::size_t>(g.width_) * static_cast<std::size_t>(g.height_);
  g.hits_.assign(n, 0);
  g.misses_.assign(n, 0);
  g.floor_n_.assign(n, 0);
  g.floor_sum_.assign(n, 0.0);

  for (const DepthSample& s : samples) {
    if (!usable(s, o.max_range_m)) continue;
    const Eigen::Vector3d d = s.point - s.origin;
    const double rel_z = d.z();  // height of the point above the camera
    const bool in_band = rel_z >= o.band_min_m && rel_z <= o.band_max_m;
    const Eigen::Vector2i end = g.cellOf(s.point.head<2>());
    // The part of the ray inside the band: parameters t in [t0, t1] of origin + t d.
    double t0 = 0.0, t1 = 1.0;
    if (d.z() != 0.0) {
      const double ta = o.band_min_m / d.z(), tb = o.band_max_m / d.z();
      t0 = std::max(0.0, std::min(ta, tb));
      t1 = std::min(1.0, std::max(ta, tb));
    } else if (!(o.band_min_m <= 0.0 && 0.0 <= o.band_max_m)) {
      t1 = -1.0;  // the camera itself is outside the band: no free space is learnt
    }
    if (t0 <= t1) {
      // Cells the band part of the ray crosses (2-D DDA), the end cell of an obstacle excluded.
      const Eigen::Vector2d a = (s.origin + t0 * d).head<2>(), b = (s.origin + t1 * d).head<2>();
      Eigen::Vector2i c = g.cellOf(a);
      const Eigen::Vector2i last = g.cellOf(b);
      const Eigen::Vector2d dir = b - a;
      Eigen::Vector2i step;
      Eigen::Vector2d t_max, t_delta;
      for (int k = 0; k < 2; ++k) {
        step[k] = dir[k] > 0 ? 1 : (dir[k] < 0 ? -1 : 0);
        if (step[k] == 0) {
          t_max[k] = t_delta[k] = std::numeric_limits<double>::infinity();
        } else {
          const double boundary = g.corner_[k] + (c[k] + (step[k] > 0 ? 1 : 0)) * r;
          t_max[k] = (boundary - a[k]) / dir[k];
          t_delta[k] = r / std::abs(dir[k]);
        }
      }
      for (int guard = 0; guard < 4 * (g.width_ + g.height_) + 4; ++guard) {
        const bool at_last = c == last;
        if (!(at_last && in_band && c == end) && g.inside(c.x(), c.y()))
          ++g.misses_[g.index(c.x(), c.y())];
        if (at_last) break;
        const int k = t_max.x() < t_max.y() ? 0 : 1;
        if (t_max[k] > 1.0) break;  // numerical end of the segment
        c[k] += step[k];
        t_max[k] += t_delta[k];
      }
    }
    if (!g.inside(end.x(), end.y())) continue;
    if (in_band) {
      ++g.hits_[g.index(end.x(), end.y())];
    } else if (rel_z < o.band_min_m) {
      ++g.floor_n_[g.index(end.x(), end.y())];
      g.floor_sum_[g.index(end.x(), end.y())] += s.point.z();
    }
  }
  return g;
}

}  // namespace rgbdi::reloc
