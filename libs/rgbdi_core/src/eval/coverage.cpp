#include "rgbdi/eval/coverage.h"

#include <algorithm>

#include "eval/nearest_stamp.h"
#include "rgbdi/eval/eval_error.h"

namespace rgbdi::eval {
namespace {
// Stamps near 1e9 s (Unix time) are only resolved to ~0.24 us in a double, so a spacing of exactly
// max_gap_periods image periods (one dropped frame) can come out a few ulps larger; this slack
// keeps that case "at most", without tolerating any real extra delay.
constexpr double kStampRoundingSlackS = 1e-6;
}  // namespace

CoverageResult computeCoverage(const Trajectory& gt, const Trajectory& est,
                               const std::vector<AssociatedPair>& pairs, double max_gap_periods) {
  CoverageResult c;
  if (gt.size() < 2 || !(gt.back().t > gt.front().t)) {
    throw EvalError("coverage: the ground truth spans no time (needs at least 2 poses)");
  }
  c.gt_duration_s = gt.back().t - gt.front().t;
  if (est.size() < 2 || pairs.size() < 2) return c;
  c.image_period_s = medianStampSpacing(est);
  const double max_gap_s = max_gap_periods * c.image_period_s + kStampRoundingSlackS;

  std::vector<AssociatedPair> by_est = pairs;
  std::sort(by_est.begin(), by_est.end(),
            [](const AssociatedPair& a, const AssociatedPair& b) { return a.est < b.est; });
  for (std::size_t k = 1; k < by_est.size(); ++k) {
    const AssociatedPair& prev = by_est[k - 1];
    const AssociatedPair& cur = by_est[k];
    if (est[cur.est].t - est[prev.est].t > max_gap_s) continue;  // tracking gap: not covered
    c.covered_s += std::max(0.0, gt[cur.gt].t - gt[prev.gt].t);
  }
  c.coverage = std::min(1.0, c.covered_s / c.gt_duration_s);
  return c;
}

}  // namespace rgbdi::eval
