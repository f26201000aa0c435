// A navigation map against the true one (rgbdi-eval --navmap, doc/navigation-maps.md
// "Accuracy"). Both grids may differ in origin, extent and frame: each true cell is looked up in
// the estimate at its centre mapped into the estimate's frame. Only the observed area counts:
// true cells whose estimate cell is known (not unknown).
//
// Strict figures count a cell right only when the estimate's state at its centre agrees. The
// tolerant ones also accept a disagreement at a true boundary that is within one cell: the truth
// makes a whole cell an obstacle when a face lies anywhere in it, and the trajectory alignment
// moves the estimate's lattice by up to half a cell, so exact points still disagree on about 1 in
// 8 boundary cells (doc/navigation-maps.md "Accuracy"). A planner inflates obstacles by the
// robot's footprint, far more than one 5 cm cell.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "rgbdi/navmap/nav_map.h"

namespace rgbdi::navmap {

struct NavMapComparison {
  std::size_t true_known = 0;            ///< true cells not unknown
  std::size_t observed = 0;              ///< of those, known in the estimate
  std::size_t true_free = 0;             ///< observed true-free cells ...
  std::size_t free_as_free = 0;          ///< ... free in the estimate
  std::size_t true_occupied = 0;         ///< observed true-occupied cells ...
  std::size_t occupied_as_occupied = 0;  ///< ... occupied in the estimate
  /// cells inside the true footprint (they and their 4 neighbours covered: the border cells
  /// follow the trajectory alignment) ...
  std::size_t true_driven = 0;
  std::size_t driven_as_free = 0;  ///< ... free in the estimate (unknown counts as not)
  std::size_t true_sloped =
      0;  ///< observed true-free cells steeper than sloped_min_deg (ramps) ...
  std::size_t sloped_as_free = 0;  ///< ... free in the estimate
  std::size_t true_edges =
      0;  ///< observed true step-edge and lowered cells (drops, holes, ramp sides) ...
  std::size_t edges_as_occupied = 0;  ///< ... occupied in the estimate
  /// Tolerant counts (the strict ones plus the boundary disagreements within one cell):
  /// a true free cell with a true obstacle among its 8 neighbours estimated occupied ...
  std::size_t free_tolerated = 0;
  /// ... a true occupied cell with a true free 8-neighbour estimated free while the estimate
  /// holds an occupied cell among the 8 neighbours of the cell looked up (the obstacle seen, one
  /// cell off) ...
  std::size_t occupied_tolerated = 0;
  std::size_t edges_tolerated = 0;  ///< ... of those, true step-edge and lowered cells
  std::size_t height_cells = 0;     ///< observed cells free in both with a ground height in both
  double height_rmse_m = 0.0;       ///< [m] RMS of (estimated - true) ground height over them
  double height_bias_m = 0.0;       ///< [m] mean of that difference
  /// Observed cells by true state (first index) and estimated state (CellState values).
  std::array<std::array<std::size_t, 7>, 7> confusion{};

  double freeRecall() const { return true_free ? double(free_as_free) / true_free : 1.0; }
  double occupiedRecall() const {
    return true_occupied ? double(occupied_as_occupied) / true_occupied : 1.0;
  }
  double drivenFree() const { return true_driven ? double(driven_as_free) / true_driven : 1.0; }
  double slopedFree() const { return true_sloped ? double(sloped_as_free) / true_sloped : 1.0; }
  double edgesOccupied() const { return true_edges ? double(edges_as_occupied) / true_edges : 1.0; }
  double freeRecallTolerant() const {
    return true_free ? double(free_as_free + free_tolerated) / true_free : 1.0;
  }
  double occupiedRecallTolerant() const {
    return true_occupied ? double(occupied_as_occupied + occupied_tolerated) / true_occupied : 1.0;
  }
  double edgesOccupiedTolerant() const {
    return true_edges ? double(edges_as_occupied + edges_tolerated) / true_edges : 1.0;
  }
  nlohmann::json toJson() const;
};

/// T_est_truth maps the true map's frame into the estimate's (for a SLAM run against a
/// simulator: the inverse of the trajectory alignment p_gt = T p_est). sloped_min_deg: the
/// true slope from which free ground counts as a ramp.
NavMapComparison compareNavMaps(const NavMap& estimate, const NavMap& truth,
                                const Eigen::Isometry3d& T_est_truth, double sloped_min_deg);

/// A picture of the comparison on the true grid (+y up, one pixel per cell): unobserved grey,
/// free in both white, occupied in both black, true free but estimated occupied red, true
/// occupied but estimated free blue (both lighter where the tolerant figures accept them: a
/// boundary disagreement within one cell), the true path's footprint green where the estimate
/// is not free. Written atomically; throws IoError naming the file.
void writeComparisonPicture(const NavMap& estimate, const NavMap& truth,
                            const Eigen::Isometry3d& T_est_truth, const std::string& path);

}  // namespace rgbdi::navmap
