// Coverage: the fraction of the ground-truth time span during which the estimate had a valid pose.
// A system that loses track and restarts must not look as good as one that tracked throughout, so
// time between two associated estimates counts only when they are close in time.
#pragma once

#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/eval/association.h"

namespace rgbdi::eval {

struct CoverageResult {
  double coverage = 0.0;        ///< covered_s / gt_duration_s, in [0, 1]
  double covered_s = 0.0;       ///< [s] ground-truth time covered
  double gt_duration_s = 0.0;   ///< [s] last minus first ground-truth stamp
  double image_period_s = 0.0;  ///< [s] median spacing of the estimate stamps (0 if < 2 poses)
};

/// For consecutive associated pairs (ordered by estimate time) whose estimate stamps are at most
/// max_gap_periods x image_period apart, the ground-truth time between their two ground-truth
/// stamps is covered. Gaps (larger spacing) and time before the first / after the last associated
/// estimate are not covered. Throws EvalError when the ground truth spans no time.
CoverageResult computeCoverage(const Trajectory& gt, const Trajectory& est,
                               const std::vector<AssociatedPair>& pairs, double max_gap_periods);

}  // namespace rgbdi::eval
