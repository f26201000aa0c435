// Complete trajectory evaluation (what `rgbdi-eval` prints): association, alignment, ATE, RPE and
// coverage, plus its JSON and human-readable forms.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/eval/alignment.h"
#include "rgbdi/eval/coverage.h"
#include "rgbdi/eval/error_statistics.h"
#include "rgbdi/eval/rpe.h"

namespace rgbdi::eval {

struct EvalOptions {
  AlignMode align = AlignMode::Se3;
  double max_dt_s = 0.02;                 ///< [s] association tolerance (TUM default)
  RpeOptions rpe;                         ///< RPE step and ground-truth matching tolerance
  double coverage_max_gap_periods = 2.0;  ///< [image periods] larger estimate gaps are not covered
};

struct EvalResult {
  EvalOptions options;
  std::size_t gt_poses = 0;
  std::size_t est_poses = 0;
  std::size_t pairs = 0;  ///< associated (gt, est) pairs used for ATE
  Alignment alignment;    ///< p_gt ~= scale * R * p_est + t
  ErrorStatistics ate;    ///< [m] position error after alignment
  RpeResult rpe;
  CoverageResult coverage;
};

/// Runs the whole evaluation. Throws EvalError when nothing associates (the message gives both
/// time spans) or when there are too few pairs for the alignment mode.
EvalResult evaluate(const Trajectory& gt, const Trajectory& est, const EvalOptions& options);

/// One JSON object with (at least) pairs, ate_rmse, ate_mean, ate_median, ate_max, scale,
/// rpe_trans_rmse, rpe_rot_rmse_deg, rpe_pairs, coverage, align, max_dt, rpe_delta.
/// Undefined values (RPE without pairs) are null.
nlohmann::json toJson(const EvalResult& result);

/// A few human-readable lines (ends with a newline).
std::string formatReport(const EvalResult& result);

}  // namespace rgbdi::eval
