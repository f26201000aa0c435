#include "rgbdi/eval/association.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace rgbdi::eval {

std::vector<AssociatedPair> associate(const Trajectory& gt, const Trajectory& est, double max_dt) {
  struct Candidate {
    double dt;
    std::size_t gt;
    std::size_t est;
  };
  // Only gt stamps inside (t_est - max_dt, t_est + max_dt) can pair with an estimate; a binary
  // search finds the window so the candidate list stays linear in practice.
  std::vector<Candidate> candidates;
  for (std::size_t j = 0; j < est.size(); ++j) {
    const double t = est[j].t;
    auto it = std::lower_bound(gt.begin(), gt.end(), t - max_dt,
                               [](const StampedPose& p, double v) { return p.t < v; });
    for (; it != gt.end() && it->t < t + max_dt; ++it) {
      const double dt = std::abs(it->t - t);
      if (dt < max_dt) candidates.push_back({dt, static_cast<std::size_t>(it - gt.begin()), j});
    }
  }
  // Same order as sorting (|dt|, t_gt, t_est) tuples: stamps are strictly increasing, so index
  // order equals stamp order.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    return std::tie(a.dt, a.gt, a.est) < std::tie(b.dt, b.gt, b.est);
  });

  std::vector<bool> gt_used(gt.size(), false);
  std::vector<bool> est_used(est.size(), false);
  std::vector<AssociatedPair> pairs;
  for (const auto& c : candidates) {
    if (gt_used[c.gt] || est_used[c.est]) continue;
    gt_used[c.gt] = true;
    est_used[c.est] = true;
    pairs.push_back({c.gt, c.est});
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const AssociatedPair& a, const AssociatedPair& b) { return a.gt < b.gt; });
  return pairs;
}

}  // namespace rgbdi::eval
