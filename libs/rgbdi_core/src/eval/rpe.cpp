#include "rgbdi/eval/rpe.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "eval/nearest_stamp.h"
#include "rgbdi/eval/eval_error.h"

namespace rgbdi::eval {
namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;
}  // namespace

RpeResult computeRpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& options) {
  if (gt.size() < 2 || est.size() < 2) {
    throw EvalError("RPE needs at least 2 poses in each trajectory (ground truth " +
                    std::to_string(gt.size()) + ", estimate " + std::to_string(est.size()) + ")");
  }
  if (!(options.delta_s > 0.0) || !std::isfinite(options.delta_s)) {
    throw EvalError("RPE delta must be a positive number of seconds");
  }
  const double gt_max_dt = options.gt_max_dt_periods * medianStampSpacing(gt);

  double sum_trans_sq = 0.0;
  double sum_rot_sq = 0.0;
  RpeResult r;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const std::size_t j = nearestStampIndex(est, est[i].t + options.delta_s);
    // evaluate_rpe.py drops the pair whose second pose is the last estimate (that is where the
    // search lands when t_i + delta runs past the end of the trajectory).
    if (j == est.size() - 1) continue;
    const std::size_t gi = nearestStampIndex(gt, est[i].t);
    const std::size_t gj = nearestStampIndex(gt, est[j].t);
    if (std::abs(gt[gi].t - est[i].t) > gt_max_dt || std::abs(gt[gj].t - est[j].t) > gt_max_dt) {
      continue;
    }
    const Eigen::Isometry3d gt_rel = gt[gi].isometry().inverse() * gt[gj].isometry();
    const Eigen::Isometry3d est_rel = est[i].isometry().inverse() * est[j].isometry();
    // Order as in evaluate_rpe.py (see rpe.h): estimated relative motion, then the true one undone.
    const Eigen::Isometry3d error = est_rel * gt_rel.inverse();
    const double trans = error.translation().norm();
    const double cos_angle = std::clamp((error.linear().trace() - 1.0) / 2.0, -1.0, 1.0);
    const double rot = std::acos(cos_angle);
    sum_trans_sq += trans * trans;
    sum_rot_sq += rot * rot;
    ++r.pairs;
  }
  if (r.pairs == 0) {
    r.trans_rmse_m = r.rot_rmse_deg = std::numeric_limits<double>::quiet_NaN();
    return r;
  }
  const double n = static_cast<double>(r.pairs);
  r.trans_rmse_m = std::sqrt(sum_trans_sq / n);
  r.rot_rmse_deg = std::sqrt(sum_rot_sq / n) * kRadToDeg;
  return r;
}

}  // namespace rgbdi::eval
