// Global correlative search of a local plan in the map's plan over x, y and yaw
// (branch-and-bound on max-pooled grids, as Cartographer's global localisation does): every
// rotation in yaw_step_deg steps, every translation at the map's cell size, scored by how
// many local obstacle cells land on the map's obstacles (2 points) or next to them (1 point).
// Not the best alignment alone: every alignment within candidate_margin of the best score is
// grouped into distinct candidate places; places whose free space conflicts with the map too
// much are dropped, the others ranked by agreement (score less conflict_penalty per conflict).
// More than one place within hypothesis_margin of the best agreement is an ambiguity
// (identical rooms, a uniform corridor).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rgbdi/reloc/plan_grid.h"
#include "rgbdi/reloc/reloc_options.h"

namespace rgbdi::reloc {

/// A 2-D rigid alignment local plan -> map plan: p_map = R(yaw) (p_local - pivot) + t.
struct PlanAlignment {
  double yaw = 0.0;                                 ///< [rad]
  Eigen::Vector2d t = Eigen::Vector2d::Zero();      ///< [m] where the pivot lands in the map
  Eigen::Vector2d pivot = Eigen::Vector2d::Zero();  ///< [m] local frame
  Eigen::Vector2d apply(const Eigen::Vector2d& p) const;
};

/// One distinct place the local plan fits.
struct PlanHypothesis {
  PlanAlignment alignment;
  int score = 0;         ///< [points] 2 per obstacle on an obstacle, 1 next to one
  double overlap = 0.0;  ///< [fraction] score / (2 x local obstacle cells)
  int compared = 0;      ///< [count] local cells that met known map cells
  int conflicts = 0;     ///< [count] of those, free-space conflicts
  double conflict_fraction = 0.0;
  /// [points] score - conflict_penalty x conflicts: what places are ranked by.
  double agreement = 0.0;
};

struct ScanSearchResult {
  int local_obstacles = 0;  ///< [count] occupied cells of the local plan
  /// Distinct places within candidate_margin of the best obstacle score, highest score first,
  /// before the free-space check (at most max_hypotheses).
  std::vector<PlanHypothesis> candidates;
  /// Those of them whose free space agrees with the map (conflict fraction within bounds) and
  /// whose agreement is within hypothesis_margin of the best one, best agreement first (ties:
  /// in candidate order). More than one is an ambiguity.
  std::vector<PlanHypothesis> places;
  std::uint64_t nodes_scored = 0;  ///< branch-and-bound nodes evaluated (cost)
  /// Too many near-best alignments or places were found to list them, and those left out may
  /// be within hypothesis_margin of the best agreement.
  bool truncated = false;
};

/// The map's plan prepared for searching (score grid and its max-pooled pyramid); immutable.
class ScanSearch {
 public:
  ScanSearch(PlanGrid map, const ScanSearchOptions& options);
  const PlanGrid& map() const { return map_; }
  /// Searches `local` with its pivot at `pivot` (local frame, e.g. the newest camera position).
  ScanSearchResult search(const PlanGrid& local, const Eigen::Vector2d& pivot) const;
  /// Score and free-space tally of one alignment (the search's own measure).
  PlanHypothesis evaluate(const PlanGrid& local, const PlanAlignment& a) const;

 private:
  /// Max over the 2^level x 2^level window starting at (ix, iy) of the score grid.
  int bound(int level, int ix, int iy) const;
  PlanGrid map_;
  ScanSearchOptions options_;
  std::vector<std::vector<std::uint8_t>> pyramid_;  ///< level 0 = the score grid
};

}  // namespace rgbdi::reloc
