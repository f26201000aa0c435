#include "rgbdi/navmap/navmap_compare.h"

#include <cmath>

namespace rgbdi::navmap {

NavMapComparison compareNavMaps(const NavMap& est, const NavMap& truth,
                                const Eigen::Isometry3d& T_est_truth, double sloped_min_deg) {
  NavMapComparison c;
  double sum = 0.0, sum2 = 0.0;
  const GridGeometry& g = truth.grid;
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.index(ix, iy);
      const CellState t = truth.state[i];
      const Eigen::Vector2d centre = g.centre(ix, iy);
      const float ht = truth.ground_z_m[i];
      const Eigen::Vector3d p_truth(centre.x(), centre.y(), std::isfinite(ht) ? ht : 0.0);
      const Eigen::Vector3d p_est = T_est_truth * p_truth;
      int ex = 0, ey = 0;
      const bool inside = est.grid.cellOf(p_est.x(), p_est.y(), &ex, &ey);
      const std::size_t j = inside ? est.grid.index(ex, ey) : 0;
      const CellState e = inside ? est.state[j] : CellState::kUnknown;
      if (truth.driven[i]) {
        ++c.true_driven;
        if (e == CellState::kFree) ++c.driven_as_free;
      }
      if (t == CellState::kUnknown) continue;
      ++c.true_known;
      if (e == CellState::kUnknown) continue;
      ++c.observed;
      if (t == CellState::kFree) {
        ++c.true_free;
        if (e == CellState::kFree) ++c.free_as_free;
        if (truth.slope_deg[i] > sloped_min_deg) {
          ++c.true_sloped;
          if (e == CellState::kFree) ++c.sloped_as_free;
        }
        const float he = est.ground_z_m[j];
        if (e == CellState::kFree && std::isfinite(ht) && std::isfinite(he)) {
          // The estimate's ground point in the true frame.
          const Eigen::Vector3d q = T_est_truth.inverse() *
                                    Eigen::Vector3d(p_est.x(), p_est.y(), static_cast<double>(he));
          const double d = q.z() - ht;
          sum += d;
          sum2 += d * d;
          ++c.height_cells;
        }
      } else {
        ++c.true_occupied;
        if (e != CellState::kFree) ++c.occupied_as_occupied;
        if (t == CellState::kStepEdge || t == CellState::kLowered) {
          ++c.true_edges;
          if (e != CellState::kFree) ++c.edges_as_occupied;
        }
      }
    }
  if (c.height_cells > 0) {
    c.height_bias_m = sum / static_cast<double>(c.height_cells);
    c.height_rmse_m = std::sqrt(sum2 / static_cast<double>(c.height_cells));
  }
  return c;
}

nlohmann::json NavMapComparison::toJson() const {
  nlohmann::json j;
  j["true_known_cells"] = true_known;
  j["observed_cells"] = observed;
  j["true_free_cells"] = true_free;
  j["free_recall"] = freeRecall();
  j["true_occupied_cells"] = true_occupied;
  j["occupied_recall"] = occupiedRecall();
  j["driven_cells"] = true_driven;
  j["driven_free"] = drivenFree();
  j["sloped_cells"] = true_sloped;
  j["sloped_free"] = slopedFree();
  j["edge_cells"] = true_edges;
  j["edges_occupied"] = edgesOccupied();
  j["height_cells"] = height_cells;
  j["height_rmse_m"] = height_rmse_m;
  j["height_bias_m"] = height_bias_m;
  return j;
}

}  // namespace rgbdi::navmap
