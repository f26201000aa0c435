#include "eval/nearest_stamp.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "rgbdi/eval/error_statistics.h"

namespace rgbdi::eval {

std::size_t nearestStampIndex(const Trajectory& traj, double t) {
  const auto it = std::lower_bound(traj.begin(), traj.end(), t,
                                   [](const StampedPose& p, double v) { return p.t < v; });
  if (it == traj.begin()) return 0;
  const std::size_t after = static_cast<std::size_t>(it - traj.begin());
  if (it == traj.end()) return after - 1;
  const std::size_t before = after - 1;
  return std::abs(traj[before].t - t) <= std::abs(traj[after].t - t) ? before : after;
}

double medianStampSpacing(const Trajectory& traj) {
  std::vector<double> spacing;
  spacing.reserve(traj.size() - 1);
  for (std::size_t k = 1; k < traj.size(); ++k) spacing.push_back(traj[k].t - traj[k - 1].t);
  return computeStatistics(std::move(spacing)).median;
}

}  // namespace rgbdi::eval
