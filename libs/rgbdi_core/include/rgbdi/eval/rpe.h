// Relative pose error over a fixed time step, following the TUM benchmark's evaluate_rpe.py with
// --fixed_delta --delta_unit s (see ../shared/data/README.md):
//   for every estimate i, j = the estimate closest in time to t_i + delta; the pair is dropped when
//   j is the last estimate. Both estimate stamps are matched to the closest ground-truth stamp and
//   the pair is dropped when either match is further than gt_max_dt_periods x the median
//   ground-truth period. Error E = (est_i^-1 est_j) (gt_i^-1 gt_j)^-1, which is what the TUM
//   script computes (ominus(ominus(est_j, est_i), ominus(gt_j, gt_i)) with ominus(a, b) = a^-1 b);
//   translation error |t(E)|, rotation error = angle of R(E).
//   Note: the README writes E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j); it has the same rotation angle
//   but a different translation (0.0215538 m instead of the README's own golden 0.0212174 m on
//   fr1/xyz), so the TUM tool's order is used to match the tool and the golden values.
// Relative motions do not depend on a global alignment, so no alignment is applied (scale 1).
#pragma once

#include <cstddef>

#include "rgbdi/common/types.h"

namespace rgbdi::eval {

struct RpeOptions {
  double delta_s = 1.0;            ///< [s] time step between the two poses of a pair
  double gt_max_dt_periods = 2.0;  ///< [ground-truth periods] max distance to the matched gt stamp
};

struct RpeResult {
  std::size_t pairs = 0;
  double trans_rmse_m = 0.0;  ///< NaN when pairs == 0
  double rot_rmse_deg = 0.0;  ///< NaN when pairs == 0
};

/// Throws EvalError when either trajectory has fewer than 2 poses or delta_s is not positive.
RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& options);

}  // namespace rgbdi::eval
