// A robust loss applied to one evaluated residual block the way Ceres' Corrector applies it, so
// that the Gauss-Newton Hessian J^T J and gradient J^T r of the corrected block are those of
// the robustified cost (Triggs' correction). Shared by the window solver and the
// marginalisation, which must linearise exactly what the solver minimises.
#pragma once

#include <ceres/loss_function.h>

#include <Eigen/Core>
#include <cmath>
#include <vector>

namespace rgbdi::estimator::detail {

/// Corrects `residuals` (n values) and every non-null Jacobian (row-major n x cols[k]) in place;
/// returns the block's cost 1/2 rho(|r|^2). `row` is scratch.
inline double applyRobustLoss(const ceres::LossFunction& loss, int n, double* residuals,
                              double* const* jacobians, const int* cols, int n_blocks,
                              std::vector<double>& row) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Eigen::Map<Eigen::VectorXd> r(residuals, n);
  const double sq = r.squaredNorm();
  double rho[3];
  loss.Evaluate(sq, rho);
  const double sqrt_rho1 = std::sqrt(rho[1]);
  double alpha = 0.0;
  if (sq != 0.0 && rho[2] > 0.0) alpha = 1.0 - std::sqrt(1.0 + 2.0 * sq * rho[2] / rho[1]);
  if (jacobians) {
    for (int k = 0; k < n_blocks; ++k) {
      if (!jacobians[k]) continue;
      Eigen::Map<RowMajor> J(jacobians[k], n, cols[k]);
      if (sq == 0.0 || alpha == 0.0) {
        J *= sqrt_rho1;
      } else {
        if (row.size() < static_cast<std::size_t>(cols[k]))
          row.resize(static_cast<std::size_t>(cols[k]));
        Eigen::Map<Eigen::RowVectorXd> rtJ(row.data(), cols[k]);
        rtJ.noalias() = r.transpose() * J;
        J = sqrt_rho1 * (J - (alpha / sq) * r * rtJ);
      }
    }
  }
  r *= sqrt_rho1 / (1.0 - alpha);
  return 0.5 * rho[0];
}

}  // namespace rgbdi::estimator::detail
