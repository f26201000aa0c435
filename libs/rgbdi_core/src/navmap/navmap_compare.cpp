#include "rgbdi/navmap/navmap_compare.h"

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/common/atomic_file.h"

namespace rgbdi::navmap {
namespace {

/// The estimate's state at a true cell's centre (unknown outside the estimate's grid).
CellState estimatedState(const NavMap& est, const NavMap& truth, int ix, int iy,
                         const Eigen::Isometry3d& T_est_truth, std::size_t* j) {
  const std::size_t i = truth.grid.index(ix, iy);
  const Eigen::Vector2d centre = truth.grid.centre(ix, iy);
  const float ht = truth.ground_z_m[i];
  const Eigen::Vector3d p_est =
      T_est_truth * Eigen::Vector3d(centre.x(), centre.y(), std::isfinite(ht) ? ht : 0.0);
  int ex = 0, ey = 0;
  if (!est.grid.cellOf(p_est.x(), p_est.y(), &ex, &ey)) return CellState::kUnknown;
  *j = est.grid.index(ex, ey);
  return est.state[*j];
}

/// Inside the true footprint: the cell and its 4 neighbours driven. The footprint's border cells
/// follow the trajectory alignment (an error of a few millimetres moves a cell centre across the
/// footprint's radius), so they are left out of the driven-cells check.
bool insideDriven(const NavMap& truth, int ix, int iy) {
  const GridGeometry& g = truth.grid;
  if (!truth.driven[g.index(ix, iy)]) return false;
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (int k = 0; k < 4; ++k)
    if (!g.contains(ix + dx[k], iy + dy[k]) || !truth.driven[g.index(ix + dx[k], iy + dy[k])])
      return false;
  return true;
}

}  // namespace

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
      std::size_t j = 0;
      const CellState e = estimatedState(est, truth, ix, iy, T_est_truth, &j);
      if (insideDriven(truth, ix, iy)) {
        ++c.true_driven;
        if (e == CellState::kFree) ++c.driven_as_free;
      }
      if (t == CellState::kUnknown) continue;
      ++c.true_known;
      if (e == CellState::kUnknown) continue;
      ++c.observed;
      ++c.confusion[static_cast<std::size_t>(t)][static_cast<std::size_t>(e)];
      if (t == CellState::kFree) {
        ++c.true_free;
        if (e == CellState::kFree) ++c.free_as_free;
        if (truth.slope_deg[i] > sloped_min_deg) {
          ++c.true_sloped;
          if (e == CellState::kFree) ++c.sloped_as_free;
        }
        const float he = est.ground_z_m[j];
        if (e == CellState::kFree && std::isfinite(ht) && std::isfinite(he)) {
          // The estimate's ground point under the true cell's centre, in the true frame.
          const Eigen::Vector3d p_est = T_est_truth * Eigen::Vector3d(centre.x(), centre.y(), ht);
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
  // {"true state": {"estimated state": cells}} over the observed cells, non-zero entries only.
  nlohmann::json confusion_json = nlohmann::json::object();
  for (std::size_t t = 0; t < confusion.size(); ++t)
    for (std::size_t e = 0; e < confusion[t].size(); ++e)
      if (confusion[t][e] > 0)
        confusion_json[toString(static_cast<CellState>(t))][toString(static_cast<CellState>(e))] =
            confusion[t][e];
  j["confusion"] = confusion_json;
  return j;
}

void writeComparisonPicture(const NavMap& est, const NavMap& truth,
                            const Eigen::Isometry3d& T_est_truth, const std::string& path) {
  const GridGeometry& g = truth.grid;
  cv::Mat image(g.height, g.width, CV_8UC3, cv::Scalar(128, 128, 128));
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.index(ix, iy);
      std::size_t j = 0;
      const CellState e = estimatedState(est, truth, ix, iy, T_est_truth, &j);
      const CellState t = truth.state[i];
      cv::Vec3b& px = image.at<cv::Vec3b>(g.height - 1 - iy, ix);  // BGR
      if (truth.driven[i] && e != CellState::kFree)
        px = cv::Vec3b(0, 170, 0);
      else if (t == CellState::kUnknown || e == CellState::kUnknown)
        continue;
      else if (t == CellState::kFree)
        px = e == CellState::kFree ? cv::Vec3b(255, 255, 255) : cv::Vec3b(0, 0, 230);
      else
        px = e == CellState::kFree ? cv::Vec3b(230, 0, 0) : cv::Vec3b(0, 0, 0);
    }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw IoError(path + ": cannot encode the PNG");
  writeFileAtomically(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

}  // namespace rgbdi::navmap
