#include "rgbdi/reloc/point_index.h"

#include <cmath>

namespace rgbdi::reloc {
namespace {
// The points thinned to one mean per voxel (first seen first), with the mean of `values`
// (double or vector) per voxel.
template <class Value>
std::vector<Eigen::Vector3d> thinWith(const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<Value>& values, double voxel_m,
                                      std::vector<Value>* values_out,
                                      std::int64_t (*keyOf)(const Eigen::Vector3i&)) {
  std::unordered_map<std::int64_t, std::size_t> slot;
  std::vector<Eigen::Vector3d> sum;
  std::vector<int> n;
  values_out->clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d& p = points[i];
    if (!p.allFinite()) continue;
    const Eigen::Vector3i c(static_cast<int>(std::floor(p.x() / voxel_m)),
                            static_cast<int>(std::floor(p.y() / voxel_m)),
                            static_cast<int>(std::floor(p.z() / voxel_m)));
    const auto [it, added] = slot.emplace(keyOf(c), sum.size());
    if (added) {
      sum.push_back(p);
      values_out->push_back(values[i]);
      n.push_back(1);
    } else {
      sum[it->second] += p;
      (*values_out)[it->second] += values[i];
      ++n[it->second];
    }
  }
  for (std::size_t i = 0; i < sum.size(); ++i) {
    sum[i] /= n[i];
    (*values_out)[i] /= n[i];
  }
  return sum;
}
}  // namespace

std::int64_t PointIndex::key(const Eigen::Vector3i& c) {
  // 21 bits per axis: +-1 million cells.
  const auto u = [](int v) { return static_cast<std::int64_t>(v + (1 << 20)) & ((1 << 21) - 1); };
  return (u(c.x()) << 42) | (u(c.y()) << 21) | u(c.z());
}

Eigen::Vector3i PointIndex::cellOf(const Eigen::Vector3d& p) const {
  return {static_cast<int>(std::floor(p.x() / cell_m_)),
          static_cast<int>(std::floor(p.y() / cell_m_)),
          static_cast<int>(std::floor(p.z() / cell_m_))};
}

std::vector<Eigen::Vector3d> PointIndex::thin(const std::vector<Eigen::Vector3d>& points,
                                              double voxel_m) {
  std::vector<double> unused;
  return thin(points, std::vector<double>(points.size(), 0.0), voxel_m, &unused);
}

std::vector<Eigen::Vector3d> PointIndex::thin(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<double>& values, double voxel_m,
                                              std::vector<double>* values_out) {
  return thinWith(points, values, voxel_m, values_out, &key);
}

std::vector<Eigen::Vector3d> PointIndex::thinDirections(
    const std::vector<Eigen::Vector3d>& points, const std::vector<Eigen::Vector3d>& directions,
    double voxel_m, std::vector<Eigen::Vector3d>* directions_out) {
  // The same voxels and order as thin(): slot i of the result is thin()'s point i.
  std::vector<Eigen::Vector3d> thinned =
      thinWith(points, directions, voxel_m, directions_out, &key);
  for (Eigen::Vector3d& d : *directions_out)
    d = d.norm() > 1e-9 ? Eigen::Vector3d(d.normalized()) : Eigen::Vector3d::Zero();
  return thinned;
}

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points, double voxel_m, double cell_m)
    : cell_m_(cell_m), points_(thin(points, voxel_m)) {
  index();
}

PointIndex::PointIndex(const std::vector<Eigen::Vector3d>& points,
                       const std::vector<Eigen::Vector3d>& view_directions, double voxel_m,
                       double cell_m)
    : cell_m_(cell_m) {
  points_ = thinDirections(points, view_directions, voxel_m, &views_);
  index();
  for (std::size_t i = 0; i < points_.size(); ++i)
    if (normals_[i].dot(views_[i]) < 0.0) normals_[i] = -normals_[i];
}

void PointIndex::index() {
  for (std::size_t i = 0; i < points_.size(); ++i)
    cells_[key(cellOf(points_[i]))].push_back(static_cast<std::uint32_t>(i));
  normals_.assign(points_.size(), Eigen::Vector3d::Zero());
  for (std::size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d& p = points_[i];
    const Eigen::Vector3i c = cellOf(p);
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
    int n = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (std::uint32_t j : it->second) {
            const Eigen::Vector3d q = points_[j] - p;
            if (q.squaredNorm() > cell_m_ * cell_m_) continue;
            mean += q;
            second += q * q.transpose();
            ++n;
          }
        }
    if (n < 5) continue;
    mean /= n;
    const Eigen::Matrix3d cov = second / n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    // A surface: the least spread well below the middle one (not a line, not a blob).
    if (es.eigenvalues()(0) > 0.3 * es.eigenvalues()(1)) continue;
    normals_[i] = es.eigenvectors().col(0).normalized();
  }
}

long PointIndex::nearest(const Eigen::Vector3d& p, double max_distance_m) const {
  const Eigen::Vector3i c = cellOf(p);
  double best = max_distance_m * max_distance_m;
  long found = -1;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto it = cells_.find(key(c + Eigen::Vector3i(dx, dy, dz)));
        if (it == cells_.end()) continue;
        for (std::uint32_t i : it->second) {
          const double d2 = (points_[i] - p).squaredNorm();
          if (d2 < best || (d2 == best && found < 0)) {
            best = d2;
            found = static_cast<long>(i);
          }
        }
      }
  return found;
}

}  // namespace rgbdi::reloc
