// Private helpers on sorted timestamp sequences shared by RPE and coverage.
#pragma once

#include <cstddef>

#include "rgbdi/common/types.h"

namespace rgbdi::eval {

/// Index of the pose whose stamp is closest to t (ties: the earlier pose). traj must be non-empty
/// and sorted by time.
std::size_t nearestStampIndex(const Trajectory& traj, double t);

/// Median of consecutive stamp differences; traj must hold at least 2 poses.
double medianStampSpacing(const Trajectory& traj);

}  // namespace rgbdi::eval
