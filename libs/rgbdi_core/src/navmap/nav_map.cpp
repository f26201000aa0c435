#include "rgbdi/navmap/nav_map.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <stdexcept>

#include "navmap/cell_points.h"
#include "navmap/drop_faces.h"
#include "navmap/layer_reuse.h"
#include "navmap/nav_map_stages.h"
#include "navmap/path_cells.h"

namespace rgbdi::navmap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr int kDx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
constexpr int kDy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
  double m = v[mid];
  if (v.size() % 2 == 0)
    m = 0.5 * (m + *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid)));
  return m;
}

/// Slope [deg] and RMS residual [m] of the plane z = a x + b y + c fitted to the centres and
/// ground heights of the cells within r cells (at least the 3 x 3 neighbourhood) of (ix, iy)
/// that lie on the same surface (ground within max_step of the centre cell's): a step higher
/// than the robot climbs does not tilt the plane of the ground beside it, and the footprint's
/// extent averages the height noise (1 cm over one 5 cm cell would be 11 deg).
void fitLocalPlane(const GridGeometry& g, const std::vector<float>& ground, int ix, int iy, int r,
                   double r2, double max_step, float* slope_deg, float* roughness) {
  const float h0 = ground[g.index(ix, iy)];
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  int n = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r2 || !g.contains(ix + dx, iy + dy)) continue;
      const float h = ground[g.index(ix + dx, iy + dy)];
      if (!std::isfinite(h) || std::abs(h - h0) > max_step) continue;
      const Eigen::Vector3d q(dx * g.cell_size_m, dy * g.cell_size_m, 1.0);
      A += q * q.transpose();
      b += q * h;
      ++n;
    }
  *slope_deg = kNaN;
  *roughness = kNaN;
  // Three cells not in a line are needed for a plane.
  if (n < 3 || std::abs(A.determinant()) < 1e-12 * std::pow(g.cell_size_m, 4)) return;
  const Eigen::Vector3d p = A.ldlt().solve(b);
  *slope_deg = static_cast<float>(std::atan(std::hypot(p.x(), p.y())) * 180.0 / M_PI);
  double sq = 0.0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r2 || !g.contains(ix + dx, iy + dy)) continue;
      const float h = ground[g.index(ix + dx, iy + dy)];
      if (!std::isfinite(h) || std::abs(h - h0) > max_step) continue;
      const double e = h - (p.x() * dx * g.cell_size_m + p.y() * dy * g.cell_size_m + p.z());
      sq += e * e;
    }
  *roughness = static_cast<float>(std::sqrt(sq / n));
}

/// Labels the plateaus: candidate cells joined to 8-neighbours whose ground differs by at most
/// max_step. A plateau the robot drove on, or level with the robot's ground (median of ground
/// minus reference within max_step), stays free; others are raised or lowered.
void classifyPlateaus(NavMap& m, const std::vector<float>& reference, double max_step) {
  const GridGeometry& g = m.grid;
  std::vector<std::int32_t> label(g.cellCount(), -1);
  std::int32_t next = 0;
  std::vector<std::size_t> members;
  for (std::size_t seed = 0; seed < g.cellCount(); ++seed) {
    if (m.state[seed] != CellState::kFree || label[seed] >= 0) continue;
    members.clear();
    std::deque<std::size_t> queue{seed};
    label[seed] = next;
    bool driven = false;
    while (!queue.empty()) {
      const std::size_t i = queue.front();
      queue.pop_front();
      members.push_back(i);
      driven = driven || m.driven[i];
      const int ix = static_cast<int>(i % static_cast<std::size_t>(g.width));
      const int iy = static_cast<int>(i / static_cast<std::size_t>(g.width));
      for (int k = 0; k < 8; ++k) {
        const int nx = ix + kDx[k], ny = iy + kDy[k];
        if (!g.contains(nx, ny)) continue;
        const std::size_t j = g.index(nx, ny);
        if (label[j] >= 0 || m.state[j] != CellState::kFree) continue;
        if (std::abs(m.ground_z_m[j] - m.ground_z_m[i]) > max_step) continue;
        label[j] = next;
        queue.push_back(j);
      }
    }
    ++next;
    if (driven) continue;
    std::vector<double> rel;
    rel.reserve(members.size());
    for (std::size_t i : members)
      if (std::isfinite(reference[i])) rel.push_back(m.ground_z_m[i] - reference[i]);
    const double r = median(rel);
    if (!std::isfinite(r) || std::abs(r) <= max_step) continue;
    for (std::size_t i : members) m.state[i] = r > 0 ? CellState::kRaised : CellState::kLowered;
  }
}

/// The floor among the ground heights `h` of the cells around a path position: the median of the
/// lowest window [h_i, h_i + depth] holding at least min_fraction of them (the lowest surface
/// seen often enough to be the floor, not a few cells of a pit or noise); the median of all when
/// no window holds that many (a ramp steeper than depth over the radius).
double lowestDenseGround(std::vector<double> h, double depth, double min_fraction) {
  if (h.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(h.begin(), h.end());
  const std::size_t need = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(min_fraction * static_cast<double>(h.size()))));
  std::size_t j = 0;
  for (std::size_t i = 0; i < h.size(); ++i) {
    j = std::max(j, i);
    while (j < h.size() && h[j] <= h[i] + depth) ++j;
    if (j - i >= need)
      return median(std::vector<double>(h.begin() + static_cast<std::ptrdiff_t>(i),
                                        h.begin() + static_cast<std::ptrdiff_t>(j)));
  }
  return median(h);
}

/// The ground under each path position: the median ground of the cells within radius whose
/// ground lies below the position (under a hand-held camera the floor beneath may be unseen and
/// the ceiling the lowest surface of a cell); NaN where there is none. Computed once per cell
/// travelled, positions closer than a cell to the last computed one take its value.
std::vector<float> groundUnderPath(const NavMap& m, const std::vector<Eigen::Vector3d>& path,
                                   double radius, double depth, double min_fraction) {
  const GridGeometry& g = m.grid;
  const int r = static_cast<int>(std::ceil(radius / g.cell_size_m));
  const double r2 = std::pow(radius / g.cell_size_m, 2);
  std::vector<float> out(path.size(), kNaN);
  std::vector<double> local;
  Eigen::Vector2d last = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  float last_ground = kNaN;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Eigen::Vector3d& p = path[k];
    int ix = 0, iy = 0;
    if (!p.allFinite() || !g.cellOf(p.x(), p.y(), &ix, &iy)) continue;
    if ((p.head<2>() - last).norm() < g.cell_size_m) {
      out[k] = last_ground;
      continue;
    }
    last = p.head<2>();
    local.clear();
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        if (dx * dx + dy * dy > r2 || !g.contains(ix + dx, iy + dy)) continue;
        const float h = m.ground_z_m[g.index(ix + dx, iy + dy)];
        if (std::isfinite(h) && h < p.z()) local.push_back(h);
      }
    last_ground =
        local.empty() ? kNaN : static_cast<float>(lowestDenseGround(local, depth, min_fraction));
    out[k] = last_ground;
  }
  return out;
}

/// Margin [0, 1] a free cell leaves to the slope and roughness limits and to the steps towards
/// free neighbours.
float cellScore(const NavMap& m, std::size_t i, int ix, int iy, const NavMapOptions& o) {
  if (m.state[i] != CellState::kFree) return 0.0f;
  if (!std::isfinite(m.ground_z_m[i])) return 1.0f;  // driven over, ground unseen
  double step = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int nx = ix + kDx[k], ny = iy + kDy[k];
    if (!m.grid.contains(nx, ny)) continue;
    const std::size_t j = m.grid.index(nx, ny);
    if (m.state[j] == CellState::kFree && std::isfinite(m.ground_z_m[j]))
      step = std::max(step, static_cast<double>(std::abs(m.ground_z_m[j] - m.ground_z_m[i])));
  }
  double s = 1.0 - step / o.max_step_m;
  if (std::isfinite(m.slope_deg[i])) s = std::min(s, 1.0 - m.slope_deg[i] / o.max_slope_deg);
  if (std::isfinite(m.roughness_m[i])) s = std::min(s, 1.0 - m.roughness_m[i] / o.max_roughness_m);
  return static_cast<float>(std::clamp(s, 0.0, 1.0));
}

}  // namespace

const char* toString(CellState s) {
  switch (s) {
    case CellState::kUnknown:
      return "unknown";
    case CellState::kFree:
      return "free";
    case CellState::kObstacle:
      return "obstacle";
    case CellState::kTooSteep:
      return "too steep";
    case CellState::kStepEdge:
      return "step edge";
    case CellState::kRaised:
      return "raised";
    case CellState::kLowered:
      return "lowered";
  }
  return "?";
}

std::size_t NavMap::count(CellState s) const {
  return static_cast<std::size_t>(std::count(state.begin(), state.end(), s));
}

GridGeometry gridAroundPath(const std::vector<Eigen::Vector3d>& path, const NavMapOptions& o) {
  o.validate();
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const Eigen::Vector3d& p : path) {
    if (!p.head<2>().allFinite()) continue;
    lo = lo.cwiseMin(p.head<2>());
    hi = hi.cwiseMax(p.head<2>());
  }
  if (!(lo.x() <= hi.x())) throw std::invalid_argument("navmap: the path has no finite position");
  const double c = o.cell_size_m, margin = o.range_m + c;
  GridGeometry g;
  g.cell_size_m = c;
  g.origin_x_m = std::floor((lo.x() - margin) / c) * c;
  g.origin_y_m = std::floor((lo.y() - margin) / c) * c;
  g.width = static_cast<int>(std::ceil((hi.x() + margin - g.origin_x_m) / c));
  g.height = static_cast<int>(std::ceil((hi.y() + margin - g.origin_y_m) / c));
  if (static_cast<double>(g.width) * g.height > 2e8)
    throw std::invalid_argument("navmap: the path spans more than 2e8 cells of " +
                                std::to_string(c) + " m");
  return g;
}

NavMap buildNavMap(const std::vector<Eigen::Vector3f>& points,
                   const std::vector<Eigen::Vector3d>& path, const NavMapOptions& o) {
  return buildNavMap(points, path, o, gridAroundPath(path, o));
}

namespace detail {

CellSurface cellSurface(const float* first, const float* last, const NavMapOptions& o) {
  CellSurface c;
  float h = 0, s = 0;
  if (!lowestSurface(first, last, o.min_points_per_cell, static_cast<float>(o.ground_band_m), &h,
                     &s))
    return c;
  c.ground_z_m = h;
  c.sigma_m = s;
  const float lo = static_cast<float>(h + o.max_step_m);
  const float hi = static_cast<float>(h + o.clearance_height_m);
  const std::size_t obstacle_points = static_cast<std::size_t>(std::upper_bound(first, last, hi) -
                                                               std::upper_bound(first, last, lo));
  c.obstacle = obstacle_points >= static_cast<std::size_t>(o.min_obstacle_points);
  const float* top = std::upper_bound(first, last, lo);
  if (top != first) c.rise_m = *(top - 1) - h;
  return c;
}

NavMap startNavMap(const std::vector<Eigen::Vector3d>& path, const NavMapOptions& o,
                   const GridGeometry& grid, NearestPose* near) {
  o.validate();
  if (path.empty()) throw std::invalid_argument("navmap: empty path");
  NavMap m;
  m.grid = grid;
  const std::size_t n = grid.cellCount();
  m.ground_z_m.assign(n, kNaN);
  m.ground_sigma_m.assign(n, kNaN);
  m.slope_deg.assign(n, kNaN);
  m.step_m.assign(n, kNaN);
  m.roughness_m.assign(n, kNaN);
  m.traversability.assign(n, kNaN);
  m.state.assign(n, CellState::kUnknown);
  m.driven = footprintCells(path, grid, o.footprint_radius_m, o.range_m);
  *near = nearestPoses(path, grid);
  return m;
}

}  // namespace detail

NavMap buildNavMap(const std::vector<Eigen::Vector3f>& points,
                   const std::vector<Eigen::Vector3d>& path, const NavMapOptions& o,
                   const GridGeometry& grid) {
  detail::NearestPose near;
  NavMap m = detail::startNavMap(path, o, grid, &near);
  const detail::CellPoints cells(points, grid);
  std::vector<std::uint8_t> obstacle(grid.cellCount(), 0);
  std::vector<float> rise(grid.cellCount(), 0.0f);
  // Lowest surface of every cell within range.
  for (std::size_t i = 0; i < grid.cellCount(); ++i) {
    if (!(near.distance_m[i] <= o.range_m)) continue;
    const detail::CellSurface c = detail::cellSurface(cells.begin(i), cells.end(i), o);
    m.ground_z_m[i] = c.ground_z_m;
    m.ground_sigma_m[i] = c.sigma_m;
    obstacle[i] = c.obstacle ? 1 : 0;
    rise[i] = c.rise_m;
  }
  detail::finishNavMap(m, near, obstacle, rise, path, o);
  return m;
}

namespace detail {

void finishNavMap(NavMap& m, const NearestPose& near, const std::vector<std::uint8_t>& obstacle,
                  const std::vector<float>& rise, const std::vector<Eigen::Vector3d>& path,
                  const NavMapOptions& o, LayerCache* cache) {
  const GridGeometry& grid = m.grid;
  const std::size_t n = grid.cellCount();
  LatticeShift shift;
  const bool reuse = cache != nullptr && cache->valid && latticeShift(grid, cache->grid, &shift);
  // The ground under the path, its height above it, and each cell's reference ground: that
  // under its nearest path position, measured, else the position less the path's height (a
  // hand-held camera moves up and down; a robot's ground is where it drives).
  std::vector<float> path_ground =
      groundUnderPath(m, path, o.path_ground_radius_m, o.max_step_m, o.path_ground_min_fraction);
  std::vector<double> above;
  for (std::size_t k = 0; k < path.size(); ++k)
    if (std::isfinite(path_ground[k])) above.push_back(path[k].z() - path_ground[k]);
  m.path_height_m = median(above);
  for (std::size_t k = 0; k < path.size(); ++k)
    if (!std::isfinite(path_ground[k]))
      path_ground[k] = static_cast<float>(path[k].z() - m.path_height_m);  // NaN without any
  std::vector<float> reference(n, kNaN);
  for (std::size_t i = 0; i < n; ++i)
    if (near.pose[i] >= 0) reference[i] = path_ground[static_cast<std::size_t>(near.pose[i])];
  // A lowest surface above the robot's clearance is an overhang with the ground under it unseen.
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(m.ground_z_m[i]) && std::isfinite(reference[i]) &&
        m.ground_z_m[i] > reference[i] + o.clearance_height_m) {
      m.ground_z_m[i] = kNaN;
      m.ground_sigma_m[i] = kNaN;
    }

  // Obstacles first: the ground of an obstacle cell is the foot of a wall or object, which the
  // plane fits of the ground beside it leave out.
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(m.ground_z_m[i]) && obstacle[i]) m.state[i] = CellState::kObstacle;
  std::vector<float> plane_ground = m.ground_z_m;
  for (std::size_t i = 0; i < n; ++i)
    if (m.state[i] == CellState::kObstacle) plane_ground[i] = kNaN;
  // Per-cell surface layers and the verdict of the other cells.
  const int plane_r =
      std::max(1, static_cast<int>(std::floor(o.footprint_radius_m / grid.cell_size_m)));
  const double plane_r2 = std::max(2.0, std::pow(o.footprint_radius_m / grid.cell_size_m, 2));
  const std::vector<std::uint8_t> refit =
      reuse ? cellsToRecompute(grid, plane_ground, shift, cache->plane_ground, plane_r)
            : std::vector<std::uint8_t>();
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::size_t i = grid.index(ix, iy);
      const float h = m.ground_z_m[i];
      if (!std::isfinite(h)) continue;
      float step = 0.0f;
      bool upper_edge = false;
      for (int k = 0; k < 8; ++k) {
        if (!grid.contains(ix + kDx[k], iy + kDy[k])) continue;
        const float hn = m.ground_z_m[grid.index(ix + kDx[k], iy + kDy[k])];
        if (!std::isfinite(hn)) continue;
        step = std::max(step, std::abs(hn - h));
        upper_edge = upper_edge || hn < h - o.max_step_m;
      }
      m.step_m[i] = step;
      if (m.state[i] == CellState::kObstacle) continue;
      if (reuse && !refit[i]) {  // same ground around it: the same plane (finite: in the old grid)
        const std::size_t j = static_cast<std::size_t>(shift.oldIndex(ix, iy));
        m.slope_deg[i] = cache->slope_deg[j];
        m.roughness_m[i] = cache->roughness_m[j];
      } else {
        fitLocalPlane(grid, plane_ground, ix, iy, plane_r, plane_r2, o.max_step_m, &m.slope_deg[i],
                      &m.roughness_m[i]);
      }
      if (m.slope_deg[i] > o.max_slope_deg)
        m.state[i] = CellState::kTooSteep;
      else if (upper_edge)
        m.state[i] = CellState::kStepEdge;
      else
        m.state[i] = CellState::kFree;
    }
  detail::markDropFaces(m, rise, reference, o);
  classifyPlateaus(m, reference, o.max_step_m);
  // Where the robot drove it could drive.
  for (std::size_t i = 0; i < n; ++i)
    if (m.driven[i]) m.state[i] = CellState::kFree;

  // Traversability: the least score over the footprint centred on the cell.
  std::vector<float> score(n, kNaN);
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::size_t i = grid.index(ix, iy);
      if (m.state[i] != CellState::kUnknown) score[i] = cellScore(m, i, ix, iy, o);
    }
  const int r = static_cast<int>(std::floor(o.footprint_radius_m / grid.cell_size_m));
  const double r2 = std::pow(o.footprint_radius_m / grid.cell_size_m, 2);
  const std::vector<std::uint8_t> rescore =
      reuse ? cellsToRecompute(grid, score, shift, cache->score, r) : std::vector<std::uint8_t>();
  for (int iy = 0; iy < grid.height; ++iy)
    for (int ix = 0; ix < grid.width; ++ix) {
      const std::size_t i = grid.index(ix, iy);
      if (m.state[i] == CellState::kUnknown) continue;
      if (reuse && !rescore[i]) {  // same scores around it (its own finite: in the old grid)
        m.traversability[i] =
            cache->traversability[static_cast<std::size_t>(shift.oldIndex(ix, iy))];
        continue;
      }
      float t = score[i];
      for (int dy = -r; dy <= r && t > 0.0f; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (dx * dx + dy * dy > r2 || !grid.contains(ix + dx, iy + dy)) continue;
          const float s = score[grid.index(ix + dx, iy + dy)];
          if (std::isfinite(s)) t = std::min(t, s);
        }
      m.traversability[i] = t;
    }
  if (cache == nullptr) return;
  cache->valid = true;
  cache->grid = grid;
  cache->plane_ground = std::move(plane_ground);
  cache->slope_deg = m.slope_deg;
  cache->roughness_m = m.roughness_m;
  cache->score = std::move(score);
  cache->traversability = m.traversability;
}

}  // namespace detail
}  // namespace rgbdi::navmap
