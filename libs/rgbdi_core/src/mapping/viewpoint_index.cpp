#include "rgbdi/mapping/viewpoint_index.h"

#include <cmath>

namespace rgbdi::mapping {

ViewpointIndex::ViewpointIndex(double min_distance_m, double min_angle_deg)
    : min_distance_m_(min_distance_m),
      cos_half_angle_(std::cos(0.5 * min_angle_deg * M_PI / 180.0)) {}

ViewpointIndex::Key ViewpointIndex::key(int ix, int iy, int iz) const {
  // 21 bits per axis: +-1 M cells, i.e. +-100 km at 0.1 m cells.
  constexpr std::int64_t kMask = (1 << 21) - 1;
  return ((static_cast<std::int64_t>(ix) & kMask) << 42) |
         ((static_cast<std::int64_t>(iy) & kMask) << 21) | (static_cast<std::int64_t>(iz) & kMask);
}

Eigen::Vector3i ViewpointIndex::cellOf(const Eigen::Vector3d& p) const {
  return (p / min_distance_m_).array().floor().cast<int>();
}

bool ViewpointIndex::covered(const Eigen::Isometry3d& T_world_cam) const {
  if (!(min_distance_m_ > 0.0)) return false;
  const Eigen::Vector3d p = T_world_cam.translation();
  const Eigen::Quaterniond q(T_world_cam.rotation());
  const Eigen::Vector3i c = cellOf(p);
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = cells_.find(key(c.x() + dx, c.y() + dy, c.z() + dz));
        if (it == cells_.end()) continue;
        for (const auto& T : it->second) {
          if ((T.translation() - p).norm() >= min_distance_m_) continue;
          // Rotation angle a between the two: |q1 . q2| = cos(a / 2).
          if (std::abs(Eigen::Quaterniond(T.rotation()).dot(q)) > cos_half_angle_) return true;
        }
      }
  return false;
}

void ViewpointIndex::add(const Eigen::Isometry3d& T_world_cam) {
  ++count_;
  if (!(min_distance_m_ > 0.0)) return;
  const Eigen::Vector3i c = cellOf(T_world_cam.translation());
  cells_[key(c.x(), c.y(), c.z())].push_back(T_world_cam);
}

}  // namespace rgbdi::mapping
