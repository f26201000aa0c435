// Residual of one 4-DOF pose-graph edge (odometry or loop) between nodes i and j, with analytic
// Jacobians. Parameters: p_i [3], yaw_i [1], p_j [3], yaw_j [1] (world frame, yaw in
// YawManifold). Residual, whitened by the edge sigmas:
//   r_t   = (Rz(yaw_i)^T (p_j - p_i) - t_ij) / sigma_pos
//   r_yaw = wrap(yaw_j - yaw_i - yaw_ij) / sigma_yaw
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "rgbdi/loop/four_dof.h"

namespace rgbdi::loop {

class FourDofEdgeFactor final : public ceres::SizedCostFunction<4, 3, 1, 3, 1> {
 public:
  /// Throws std::invalid_argument when a sigma is not positive and finite.
  FourDofEdgeFactor(const FourDofDelta& measured, double sigma_pos_m, double sigma_yaw_rad);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The whitened residual for the given node states (no Jacobians).
  Eigen::Vector4d residual(const double* p_i, double yaw_i, const double* p_j, double yaw_j) const;

 private:
  FourDofDelta measured_;
  double w_pos_;  ///< [1/m] 1 / sigma_pos
  double w_yaw_;  ///< [1/rad] 1 / sigma_yaw
};

}  // namespace rgbdi::loop
