#include "rgbdi/frontend/occlusion_test.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rgbdi::frontend {

WindowPlaneFit fitWindowPlane(const cv::Mat& depth_m, const Eigen::Vector2d& uv, int half_window_px,
                              int step_px) {
  if (depth_m.type() != CV_32FC1)
    throw std::invalid_argument("fitWindowPlane: depth image must be CV_32FC1 metres, got type " +
                                std::to_string(depth_m.type()));
  if (step_px < 1) throw std::invalid_argument("fitWindowPlane: step must be positive");
  WindowPlaneFit fit;
  if (!(uv.allFinite() && std::abs(uv.x()) < 1e6 && std::abs(uv.y()) < 1e6)) return fit;
  const int uc = static_cast<int>(std::lround(uv.x())), vc = static_cast<int>(std::lround(uv.y()));
  // Normal equations of w = a du + b dv + c (w = 1/z), offsets from the centre keep them well
  // conditioned; the residual sum of squares follows from the same sums.
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atw = Eigen::Vector3d::Zero();
  double ww = 0.0;
  const int k = half_window_px / step_px;
  for (int j = -k; j <= k; ++j) {
    const int v = vc + j * step_px;
    if (v < 0 || v >= depth_m.rows) continue;
    const float* row = depth_m.ptr<float>(v);
    for (int i = -k; i <= k; ++i) {
      const int u = uc + i * step_px;
      if (u < 0 || u >= depth_m.cols) continue;
      ++fit.grid_samples;
      const float z = row[u];
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      const Eigen::Vector3d a(i, j, 1.0);
      const double w = 1.0 / z;
      ata.noalias() += a * a.transpose();
      atw += a * w;
      ww += w * w;
      ++fit.samples;
    }
  }
  if (fit.samples < 4) return fit;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return fit;
  const Eigen::Vector3d x = ldlt.solve(atw);
  // |A x - w|^2 = w.w - x.(A^T w) at the least-squares solution; clamp rounding below zero.
  const double rss = std::max(0.0, ww - x.dot(atw));
  fit.rms_residual_inv_m = std::sqrt(rss / fit.samples);
  return fit;
}

bool straddlesOcclusion(const cv::Mat& depth_m, const Eigen::Vector2d& uv,
                        const FrontendOptions& options) {
  if (options.occlusion_window_px <= 0) return false;
  const WindowPlaneFit fit =
      fitWindowPlane(depth_m, uv, options.occlusion_window_px, options.occlusion_sample_step_px);
  if (fit.grid_samples == 0 ||
      fit.samples < options.occlusion_min_valid_fraction * fit.grid_samples || fit.samples < 4)
    return false;
  return fit.rms_residual_inv_m > options.occlusion_max_residual_sigmas * options.depth_noise_coeff;
}

}  // namespace rgbdi::frontend
