// Timestamp association of ground truth and estimate, with the semantics of the TUM benchmark's
// associate.py: every (gt, est) pair closer than max_dt is a candidate; candidates are taken
// greedily by increasing |dt| (ties by gt stamp, then est stamp), each stamp used at most once.
#pragma once

#include <cstddef>
#include <vector>

#include "rgbdi/common/types.h"

namespace rgbdi::eval {

struct AssociatedPair {
  std::size_t gt = 0;   ///< index into the ground-truth trajectory
  std::size_t est = 0;  ///< index into the estimated trajectory
};

/// One-to-one association, |t_gt - t_est| < max_dt (strict, as associate.py). Both trajectories
/// must be sorted by time (readTum guarantees it). Result sorted by ground-truth index.
std::vector<AssociatedPair> associate(const Trajectory& gt, const Trajectory& est, double max_dt);

}  // namespace rgbdi::eval
