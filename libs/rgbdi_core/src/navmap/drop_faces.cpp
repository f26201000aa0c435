#include "navmap/drop_faces.h"

#include <cmath>
#include <cstddef>

namespace rgbdi::navmap::detail {
namespace {

constexpr int kDx[8] = {-1, 0, 1, -1, 1, -1, 0, 1};
constexpr int kDy[8] = {-1, -1, -1, 0, 0, 1, 1, 1};

}  // namespace

void markDropFaces(NavMap& m, const std::vector<float>& rise, const std::vector<float>& reference,
                   const NavMapOptions& o) {
  if (!(o.drop_face_min_rise_m > 0.0)) return;
  const GridGeometry& g = m.grid;
  auto isFace = [&](std::size_t i) {
    return m.state[i] == CellState::kFree && rise[i] >= o.drop_face_min_rise_m &&
           m.ground_z_m[i] <= reference[i] - o.drop_face_min_depth_m;
  };
  std::vector<std::size_t> faces;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.index(ix, iy);
      if (!isFace(i)) continue;
      // The lower side seen as floor (a neighbour at the face's foot that is no face itself):
      // a step down the robot can see and climb, not a drop into the unseen.
      bool lower_floor_seen = false;
      for (int k = 0; k < 8 && !lower_floor_seen; ++k) {
        if (!g.contains(ix + kDx[k], iy + kDy[k])) continue;
        const std::size_t j = g.index(ix + kDx[k], iy + kDy[k]);
        lower_floor_seen = m.state[j] == CellState::kFree && rise[j] < o.drop_face_min_rise_m &&
                           std::abs(m.ground_z_m[j] - m.ground_z_m[i]) < o.drop_face_min_depth_m;
      }
      if (!lower_floor_seen) faces.push_back(i);
    }
  std::vector<std::size_t> rim;
  for (std::size_t i : faces) {
    m.state[i] = CellState::kStepEdge;
    const int ix = static_cast<int>(i % static_cast<std::size_t>(g.width));
    const int iy = static_cast<int>(i / static_cast<std::size_t>(g.width));
    for (int k = 0; k < 8; ++k) {
      if (!g.contains(ix + kDx[k], iy + kDy[k])) continue;
      const std::size_t j = g.index(ix + kDx[k], iy + kDy[k]);
      if (m.state[j] == CellState::kFree &&
          m.ground_z_m[j] >= m.ground_z_m[i] + o.drop_face_min_depth_m)
        rim.push_back(j);
    }
  }
  for (std::size_t j : rim) m.state[j] = CellState::kStepEdge;
}

}  // namespace rgbdi::navmap::detail
