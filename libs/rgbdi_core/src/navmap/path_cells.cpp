#include "navmap/path_cells.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rgbdi::navmap::detail {
namespace {

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace

std::vector<std::uint8_t> footprintCells(const std::vector<Eigen::Vector3d>& path,
                                         const GridGeometry& grid, double radius,
                                         double max_join_m) {
  std::vector<std::uint8_t> out(grid.cellCount(), 0);
  auto mark = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const double c = grid.cell_size_m;
    const int x0 = std::max(
        0, static_cast<int>(std::floor((std::min(a.x(), b.x()) - radius - grid.origin_x_m) / c)));
    const int y0 = std::max(
        0, static_cast<int>(std::floor((std::min(a.y(), b.y()) - radius - grid.origin_y_m) / c)));
    const int x1 = std::min(
        grid.width - 1,
        static_cast<int>(std::floor((std::max(a.x(), b.x()) + radius - grid.origin_x_m) / c)));
    const int y1 = std::min(
        grid.height - 1,
        static_cast<int>(std::floor((std::max(a.y(), b.y()) + radius - grid.origin_y_m) / c)));
    for (int iy = y0; iy <= y1; ++iy)
      for (int ix = x0; ix <= x1; ++ix)
        if (distanceToSegment(grid.centre(ix, iy), a, b) <= radius) out[grid.index(ix, iy)] = 1;
  };
  for (std::size_t i = 0; i < path.size(); ++i) {
    const Eigen::Vector2d a = path[i].head<2>();
    if (!a.allFinite()) continue;
    const bool join = i + 1 < path.size() && path[i + 1].head<2>().allFinite() &&
                      (path[i + 1].head<2>() - a).norm() < max_join_m;
    mark(a, join ? Eigen::Vector2d(path[i + 1].head<2>()) : a);
  }
  return out;
}

NearestPose nearestPoses(const std::vector<Eigen::Vector3d>& path, const GridGeometry& grid) {
  NearestPose np;
  const std::size_t n = grid.cellCount();
  np.pose.assign(n, -1);
  np.distance_m.assign(n, std::numeric_limits<float>::infinity());
  auto dist = [&](int ix, int iy, std::int32_t pose) {
    return static_cast<float>(
        (grid.centre(ix, iy) - path[static_cast<std::size_t>(pose)].head<2>()).norm());
  };
  for (std::size_t p = 0; p < path.size(); ++p) {
    int ix = 0, iy = 0;
    if (!grid.cellOf(path[p].x(), path[p].y(), &ix, &iy)) continue;
    const std::size_t i = grid.index(ix, iy);
    const float d = dist(ix, iy, static_cast<std::int32_t>(p));
    if (d < np.distance_m[i]) {  // strict: the first of equally near poses wins
      np.distance_m[i] = d;
      np.pose[i] = static_cast<std::int32_t>(p);
    }
  }
  auto relax = [&](int ix, int iy, int nx, int ny) {
    if (!grid.contains(nx, ny)) return;
    const std::int32_t cand = np.pose[grid.index(nx, ny)];
    if (cand < 0) return;
    const std::size_t i = grid.index(ix, iy);
    const float d = dist(ix, iy, cand);
    if (d < np.distance_m[i] || (d == np.distance_m[i] && cand < np.pose[i])) {
      np.distance_m[i] = d;
      np.pose[i] = cand;
    }
  };
  for (int round = 0; round < 2; ++round) {
    for (int iy = 0; iy < grid.height; ++iy)
      for (int ix = 0; ix < grid.width; ++ix) {
        relax(ix, iy, ix - 1, iy);
        relax(ix, iy, ix - 1, iy - 1);
        relax(ix, iy, ix, iy - 1);
        relax(ix, iy, ix + 1, iy - 1);
      }
    for (int iy = grid.height - 1; iy >= 0; --iy)
      for (int ix = grid.width - 1; ix >= 0; --ix) {
        relax(ix, iy, ix + 1, iy);
        relax(ix, iy, ix + 1, iy + 1);
        relax(ix, iy, ix, iy + 1);
        relax(ix, iy, ix - 1, iy + 1);
      }
  }
  return np;
}

}  // namespace rgbdi::navmap::detail
