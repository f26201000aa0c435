#include "rgbdi/eval/evaluate.h"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "rgbdi/eval/association.h"
#include "rgbdi/eval/eval_error.h"

namespace rgbdi::eval {
namespace {

std::string spanText(const Trajectory& traj) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << "[" << traj.front().t << ", " << traj.back().t
     << "] s";
  return os.str();
}

// JSON has no NaN: undefined values become null.
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options) {
  if (gt.empty() || est.empty()) throw EvalError("evaluate: empty trajectory");
  if (!(options.max_dt_s > 0.0)) throw EvalError("evaluate: max_dt must be positive");

  EvalResult r;
  r.options = options;
  r.gt_poses = gt.size();
  r.est_poses = est.size();

  const std::vector<AssociatedPair> pairs = associate(gt, est, options.max_dt_s);
  r.pairs = pairs.size();
  if (pairs.empty()) {
    std::ostringstream msg;
    msg << "no estimate stamp is within max_dt " << options.max_dt_s
        << " s of a ground-truth stamp (ground truth spans " << spanText(gt) << ", estimate spans "
        << spanText(est) << ")";
    throw EvalError(msg.str());
  }

  std::vector<Eigen::Vector3d> p_est;
  std::vector<Eigen::Vector3d> p_gt;
  p_est.reserve(pairs.size());
  p_gt.reserve(pairs.size());
  for (const auto& pr : pairs) {
    p_est.push_back(est[pr.est].p);
    p_gt.push_back(gt[pr.gt].p);
  }
  r.alignment = alignPositions(p_est, p_gt, options.align);

  std::vector<double> errors;
  errors.reserve(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    errors.push_back((p_gt[k] - r.alignment.apply(p_est[k])).norm());
  }
  r.ate = computeStatistics(std::move(errors));
  r.rpe = computeRpe(gt, est, options.rpe);
  r.coverage = computeCoverage(gt, est, pairs, options.coverage_max_gap_periods);
  return r;
}

nlohmann::json toJson(const EvalResult& r) {
  nlohmann::json j;
  j["align"] = alignModeName(r.options.align);
  j["max_dt"] = r.options.max_dt_s;
  j["rpe_delta"] = r.options.rpe.delta_s;
  j["gt_poses"] = r.gt_poses;
  j["est_poses"] = r.est_poses;
  j["pairs"] = r.pairs;
  j["ate_rmse"] = number(r.ate.rmse);
  j["ate_mean"] = number(r.ate.mean);
  j["ate_median"] = number(r.ate.median);
  j["ate_max"] = number(r.ate.max);
  j["scale"] = r.alignment.scale;
  nlohmann::json rotation = nlohmann::json::array();
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) rotation.push_back(r.alignment.R(row, col));
  }
  j["alignment"] = {{"R_row_major", rotation},
                    {"t", {r.alignment.t.x(), r.alignment.t.y(), r.alignment.t.z()}},
                    {"scale", r.alignment.scale}};
  j["rpe_pairs"] = r.rpe.pairs;
  j["rpe_trans_rmse"] = number(r.rpe.trans_rmse_m);
  j["rpe_rot_rmse_deg"] = number(r.rpe.rot_rmse_deg);
  j["coverage"] = r.coverage.coverage;
  j["covered_s"] = r.coverage.covered_s;
  j["gt_duration_s"] = r.coverage.gt_duration_s;
  j["image_period_s"] = r.coverage.image_period_s;
  return j;
}

std::string formatReport(const EvalResult& r) {
  std::ostringstream os;
  os << std::setprecision(6);
  os << "pairs      " << r.pairs << " associated within " << r.options.max_dt_s
     << " s (ground truth " << r.gt_poses << " poses, estimate " << r.est_poses << " poses)\n";
  os << "alignment  " << alignModeName(r.options.align) << ", scale " << r.alignment.scale << "\n";
  os << "ATE [m]    rmse " << r.ate.rmse << "  mean " << r.ate.mean << "  median " << r.ate.median
     << "  max " << r.ate.max << "\n";
  os << "RPE " << r.options.rpe.delta_s << " s  " << r.rpe.pairs << " pairs";
  if (r.rpe.pairs > 0) {
    os << ", translation rmse " << r.rpe.trans_rmse_m << " m, rotation rmse " << r.rpe.rot_rmse_deg
       << " deg";
  } else {
    os << " (trajectory shorter than the step: no RPE)";
  }
  os << "\n";
  os << "coverage   " << r.coverage.coverage << " (" << r.coverage.covered_s << " s of "
     << r.coverage.gt_duration_s << " s ground truth; estimate period " << r.coverage.image_period_s
     << " s)\n";
  return os.str();
}

}  // namespace rgbdi::eval
