#include "rgbdi/navmap/navmap_compare.h"

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/common/atomic_file.h"

namespace rgbdi::navmap {
namespace {

bool isOccupied(CellState s) { return s != CellState::kFree && s != CellState::kUnknown; }

/// Where a true cell's centre falls in the estimate: its cell (ex, ey) and state (unknown
/// outside the estimate's grid, ex = ey = -1).
struct EstimateSample {
  CellState state = CellState::kUnknown;
  int ex = -1, ey = -1;
  std::size_t index = 0;
};

EstimateSample sampleEstimate(const NavMap& est, const NavMap& truth, int ix, int iy,
                              const Eigen::Isometry3d& T_est_truth) {
  const std::size_t i = truth.grid.index(ix, iy);
  const Eigen::Vector2d centre = truth.grid.centre(ix, iy);
  const float ht = truth.ground_z_m[i];
  const Eigen::Vector3d p_est =
      T_est_truth * Eigen::Vector3d(centre.x(), centre.y(), std::isfinite(ht) ? ht : 0.0);
  EstimateSample s;
  if (!est.grid.cellOf(p_est.x(), p_est.y(), &s.ex, &s.ey)) return s;
  s.index = est.grid.index(s.ex, s.ey);
  s.state = est.state[s.index];
  return s;
}

/// Whether one of the 8 neighbours of (ix, iy) in `map` is in a state `wanted` accepts.
template <typename Wanted>
bool anyNeighbour(const NavMap& map, int ix, int iy, Wanted wanted) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if ((dx != 0 || dy != 0) && map.grid.contains(ix + dx, iy + dy) &&
          wanted(map.state[map.grid.index(ix + dx, iy + dy)]))
        return true;
  return false;
}

/// A strict disagreement the tolerant figures accept (header): true free estimated occupied
/// next to a true obstacle, or true occupied estimated free next to true free ground while the
/// estimate has an obstacle one cell off.
bool toleratedDisagreement(const NavMap& est, const NavMap& truth, int ix, int iy,
                           const EstimateSample& e) {
  const CellState t = truth.state[truth.grid.index(ix, iy)];
  if (t == CellState::kFree && isOccupied(e.state)) return anyNeighbour(truth, ix, iy, isOccupied);
  if (isOccupied(t) && e.state == CellState::kFree)
    return anyNeighbour(truth, ix, iy, [](CellState s) { return s == CellState::kFree; }) &&
           anyNeighbour(est, e.ex, e.ey, isOccupied);
  return false;
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
      const EstimateSample sample = sampleEstimate(est, truth, ix, iy, T_est_truth);
      const CellState e = sample.state;
      const std::size_t j = sample.index;
      const bool tolerated = toleratedDisagreement(est, truth, ix, iy, sample);
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
        if (tolerated) ++c.free_tolerated;
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
        if (tolerated) ++c.occupied_tolerated;
        if (t == CellState::kStepEdge || t == CellState::kLowered) {
          ++c.true_edges;
          if (e != CellState::kFree) ++c.edges_as_occupied;
          if (tolerated) ++c.edges_tolerated;
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
  // Tolerant: boundary disagreements within one cell accepted (navmap_compare.h).
  j["free_tolerated_cells"] = free_tolerated;
  j["free_recall_tolerant"] = freeRecallTolerant();
  j["occupied_tolerated_cells"] = occupied_tolerated;
  j["occupied_recall_tolerant"] = occupiedRecallTolerant();
  j["edges_tolerated_cells"] = edges_tolerated;
  j["edges_occupied_tolerant"] = edgesOccupiedTolerant();
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
      const EstimateSample sample = sampleEstimate(est, truth, ix, iy, T_est_truth);
      const CellState e = sample.state;
      const CellState t = truth.state[i];
      const bool tolerated = toleratedDisagreement(est, truth, ix, iy, sample);
      cv::Vec3b& px = image.at<cv::Vec3b>(g.height - 1 - iy, ix);  // BGR
      if (truth.driven[i] && e != CellState::kFree)
        px = cv::Vec3b(0, 170, 0);
      else if (t == CellState::kUnknown || e == CellState::kUnknown)
        continue;
      else if (t == CellState::kFree)
        px = e == CellState::kFree ? cv::Vec3b(255, 255, 255)
             : tolerated           ? cv::Vec3b(160, 160, 255)
                                   : cv::Vec3b(0, 0, 230);
      else
        px = e != CellState::kFree ? cv::Vec3b(0, 0, 0)
             : tolerated           ? cv::Vec3b(255, 190, 150)
                                   : cv::Vec3b(230, 0, 0);
    }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw IoError(path + ": cannot encode the PNG");
  writeFileAtomically(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

}  // namespace rgbdi::navmap
