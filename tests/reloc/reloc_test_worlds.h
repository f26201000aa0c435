// Synthetic depth for the geometric relocalisation tests: rooms of axis-aligned walls and boxes
// (walls on cell centres of the 5 cm lattice) ray-cast from one camera position; rotations by
// 90 deg and shifts by whole cells map the plans onto each other exactly.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "rgbdi/reloc/plan_grid.h"

namespace rgbdi::reloc::test {

constexpr double kCell = 0.05;
constexpr double kCamZ = 0.3;  ///< camera height above the floor (z = 0)

/// Cell-centre coordinate of lattice index i.
inline double at(int i) { return (i + 0.5) * kCell; }

/// Floor samples on the lattice of [x0, x1] x [y0, y1] (every second cell, inclusive) at
/// height z, seen from `cam`.
inline void addFloor(int x0, int y0, int x1, int y1, double z, const Eigen::Vector3d& cam,
                     std::vector<DepthSample>* out) {
  for (int i = x0; i <= x1; i += 2)
    for (int j = y0; j <= y1; j += 2) out->push_back({cam, Eigen::Vector3d(at(i), at(j), z)});
}

/// An axis-aligned box (a room's walls seen from inside, or an obstacle seen from outside).
struct Box {
  double x0, y0, x1, y1;  ///< [m]
};
inline Box cells(int x0, int y0, int x1, int y1) { return {at(x0), at(y0), at(x1), at(y1)}; }

/// What a 360-degree depth camera at `cam` sees of the boxes: the nearest wall along each of
/// 1440 horizontal rays, at three heights in the obstacle band, and four floor samples (z = 0)
/// before the wall on every fourth ray.
inline std::vector<DepthSample> scan(const std::vector<Box>& boxes, const Eigen::Vector3d& cam) {
  std::vector<DepthSample> out;
  for (int k = 0; k < 1440; ++k) {
    const double a = (k + 0.37) * 2.0 * M_PI / 1440.0;  // off the diagonals
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = 1e9;
    for (const Box& b : boxes) {
      for (double x : {b.x0, b.x1})
        if (d.x() != 0.0) {
          const double t = (x - cam.x()) / d.x();
          const double y = cam.y() + t * d.y();
          if (t > 0 && y >= b.y0 && y <= b.y1) best = std::min(best, t);
        }
      for (double y : {b.y0, b.y1})
        if (d.y() != 0.0) {
          const double t = (y - cam.y()) / d.y();
          const double x = cam.x() + t * d.x();
          if (t > 0 && x >= b.x0 && x <= b.x1) best = std::min(best, t);
        }
    }
    if (best > 1e8) continue;
    const Eigen::Vector2d hit = cam.head<2>() + best * d;
    for (double dz : {-0.1, 0.0, 0.2})
      out.push_back({cam, Eigen::Vector3d(hit.x(), hit.y(), kCamZ + dz)});
    if (k % 4 == 0)
      for (double f : {0.2, 0.4, 0.6, 0.8}) {
        const Eigen::Vector2d p = cam.head<2>() + f * best * d;
        out.push_back({cam, Eigen::Vector3d(p.x(), p.y(), 0.0)});
      }
  }
  return out;
}

/// An asymmetric room: 3 x 2 m walls, a crate in one corner and a pillar, seen from `cam`
/// (the room shifted by ox, oy cells).
inline std::vector<Box> asymmetricRoomBoxes(int ox = 0, int oy = 0) {
  return {cells(ox + 0, oy + 0, ox + 59, oy + 39), cells(ox + 5, oy + 28, ox + 14, oy + 34),
          cells(ox + 40, oy + 8, ox + 42, oy + 10)};
}
inline std::vector<DepthSample> asymmetricRoom(const Eigen::Vector3d& cam, int ox = 0, int oy = 0) {
  return scan(asymmetricRoomBoxes(ox, oy), cam);
}

/// Every sample moved by a yaw about z and a translation.
inline std::vector<DepthSample> moved(const std::vector<DepthSample>& in, double yaw,
                                      const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  std::vector<DepthSample> out;
  for (const DepthSample& d : in) out.push_back({T * d.origin, T * d.point});
  return out;
}

}  // namespace rgbdi::reloc::test
