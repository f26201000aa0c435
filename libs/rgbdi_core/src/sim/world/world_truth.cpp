#include "rgbdi/sim/world_truth.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace rgbdi::sim {
namespace {

using Interval = std::pair<double, double>;  ///< [bottom, top] of a solid on a vertical line

/// The solids a vertical line through (x, y) crosses, merged where they touch, bottom up; only
/// the primitives `candidates` (those whose bounds reach the line's cell).
std::vector<Interval> solidsAlong(const Scene& scene, const std::vector<std::uint32_t>& candidates,
                                  double x, double y, double z_lo, double z_hi) {
  std::vector<Interval> cuts;
  const Eigen::Vector3d down(0, 0, -1), up(0, 0, 1);
  const double length = z_hi - z_lo;
  for (std::uint32_t p : candidates) {
    const Eigen::AlignedBox3d& b = scene.primitiveBounds(p);
    if (x < b.min().x() || x > b.max().x() || y < b.min().y() || y > b.max().y()) continue;
    PrimitiveHit top, bottom;
    // Every primitive is convex: the line enters it once from above and once from below.
    if (!scene.intersectPrimitive(p, Eigen::Vector3d(x, y, z_hi), down, length, top)) continue;
    if (!scene.intersectPrimitive(p, Eigen::Vector3d(x, y, z_lo), up, length, bottom)) continue;
    cuts.emplace_back(z_lo + bottom.t, z_hi - top.t);
  }
  std::sort(cuts.begin(), cuts.end());
  std::vector<Interval> merged;
  for (const Interval& c : cuts) {
    if (!merged.empty() && c.first <= merged.back().second + 1e-6)
      merged.back().second = std::max(merged.back().second, c.second);
    else
      merged.push_back(c);
  }
  return merged;
}

/// Path positions at least a cell apart (the nearest-position search below: within half a cell).
std::vector<Eigen::Vector2d> thinnedPath(const std::vector<Eigen::Vector3d>& path, double min_gap,
                                         std::vector<double>* z) {
  std::vector<Eigen::Vector2d> xy;
  for (const Eigen::Vector3d& p : path) {
    if (!p.allFinite()) continue;
    if (!xy.empty() && (xy.back() - p.head<2>()).norm() < min_gap) continue;
    xy.push_back(p.head<2>());
    z->push_back(p.z());
  }
  return xy;
}

}  // namespace

WorldSurface worldSurface(const Scene& scene, const navmap::GridGeometry& grid) {
  const Eigen::AlignedBox3d world = scene.bounds();
  const double z_lo = world.min().z() - 1.0, z_hi = world.max().z() + 1.0;
  WorldSurface out;
  out.column_top_m.assign(grid.cellCount(), std::numeric_limits<float>::quiet_NaN());
  // Line offsets from the cell centre: a quarter cell apart, the outer ones just inside the
  // cell's edges, so that a face anywhere in the cell lies between two lines.
  const double h = 0.5 * grid.cell_size_m, inset = 1e-4 * grid.cell_size_m;
  std::array<double, kLinesPerSide> offsets{};
  for (int k = 0; k < kLinesPerSide; ++k)
    offsets[static_cast<std::size_t>(k)] =
        std::clamp(-h + 2.0 * h * k / (kLinesPerSide - 1), -h + inset, h - inset);
  std::vector<std::uint32_t> candidates;
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const Eigen::Vector2d c = grid.centre(ix, iy);
      candidates.clear();
      for (std::uint32_t p = 0; p < scene.primitiveCount(); ++p) {
        const Eigen::AlignedBox3d& b = scene.primitiveBounds(p);
        if (b.max().x() >= c.x() - h && b.min().x() <= c.x() + h && b.max().y() >= c.y() - h &&
            b.min().y() <= c.y() + h)
          candidates.push_back(p);
      }
      double ground_lo = std::numeric_limits<double>::infinity(), ground_hi = -ground_lo;
      int lines_with_solid = 0;
      for (int k = 0; k < kLinesPerSide * kLinesPerSide; ++k) {
        const double x = c.x() + offsets[static_cast<std::size_t>(k % kLinesPerSide)];
        const double y = c.y() + offsets[static_cast<std::size_t>(k / kLinesPerSide)];
        const std::vector<Interval> solids = solidsAlong(scene, candidates, x, y, z_lo, z_hi);
        for (const Interval& s : solids)
          out.points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                  static_cast<float>(s.second));
        if (!solids.empty()) {
          ++lines_with_solid;
          ground_lo = std::min(ground_lo, solids.front().second);
          ground_hi = std::max(ground_hi, solids.front().second);
        }
      }
      if (lines_with_solid == kLinesPerSide * kLinesPerSide)
        out.column_top_m[grid.index(ix, iy)] = static_cast<float>(ground_hi);
      if (ground_hi - ground_lo > kFaceMinM)
        for (double z = ground_lo + kFaceStepM; z < ground_hi; z += kFaceStepM)
          out.points.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()),
                                  static_cast<float>(z));
    }
  return out;
}

std::vector<Eigen::Vector3d> truePath(const SimulatedSequence& sequence) {
  std::vector<Eigen::Vector3d> path;
  path.reserve(sequence.frameCount());
  for (std::size_t i = 0; i < sequence.frameCount(); ++i)
    path.push_back(sequence.groundTruth(sequence.frameExposureTime(i)).T_world_body.translation());
  return path;
}

navmap::NavMap trueNavMap(const WorldSurface& surface, const std::vector<Eigen::Vector3d>& path,
                          const navmap::NavMapOptions& o, const navmap::GridGeometry& grid) {
  navmap::NavMap m = navmap::buildNavMap(surface.points, path, o, grid);
  if (!std::isfinite(m.path_height_m)) return m;
  std::vector<double> path_z;
  const std::vector<Eigen::Vector2d> xy = thinnedPath(path, grid.cell_size_m, &path_z);
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::size_t i = grid.index(ix, iy);
      if (m.state[i] != navmap::CellState::kUnknown || !std::isfinite(surface.column_top_m[i]))
        continue;
      const Eigen::Vector2d c = grid.centre(ix, iy);
      double best = std::numeric_limits<double>::infinity();
      std::size_t nearest = 0;
      for (std::size_t k = 0; k < xy.size(); ++k) {
        const double d = (xy[k] - c).squaredNorm();
        if (d < best) {
          best = d;
          nearest = k;
        }
      }
      if (!(std::sqrt(best) <= o.range_m)) continue;
      const double ground = path_z[nearest] - m.path_height_m;
      if (surface.column_top_m[i] > ground + o.clearance_height_m) {
        m.state[i] = navmap::CellState::kObstacle;
        m.traversability[i] = 0.0f;
      }
    }
  return m;
}

navmap::NavMap trueNavMap(const SimulatedSequence& sequence, const navmap::NavMapOptions& options) {
  const std::vector<Eigen::Vector3d> path = truePath(sequence);
  const navmap::GridGeometry grid = navmap::gridAroundPath(path, options);
  return trueNavMap(worldSurface(sequence.scene(), grid), path, options, grid);
}

}  // namespace rgbdi::sim
