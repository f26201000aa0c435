// Residual of one 4-DOF pose-graph edge (odometry or loop) between nodes i and j, with analytic
// Jacobians. Parameters: x_i, x_j = [px, py, pz, yaw] of each node (world frame; the block lives
// on NodeStateManifold, whose yaw wraps). Residual, whitened by the edge sigmas:
//   r_t   = (Rz(yaw_i)^T (p_j - p_i) - t_ij) / sigma_pos
//   r_yaw = wrap(yaw_j - yaw_i - yaw_ij) / sigma_yaw
#pragma once

#include <ceres/manifold.h>
#include <ceres/product_manifold.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>

#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/yaw_manifold.h"

namespace rgbdi::loop {

/// Manifold of a node state [px, py, pz, yaw]: Euclidean position, wrapping yaw.
using NodeStateManifold = ceres::ProductManifold<ceres::EuclideanManifold<3>, YawManifold>;

class FourDofEdgeFactor final : public ceres::SizedCostFunction<4, 4, 4> {
 public:
  /// Throws std::invalid_argument when a sigma is not positive and finite.
  FourDofEdgeFactor(const FourDofDelta& measured, double sigma_pos_m, double sigma_yaw_rad);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// The whitened residual for the given node states (no Jacobians).
  Eigen::Vector4d residual(const double* x_i, const double* x_j) const;

 private:
  FourDofDelta measured_;
  double w_pos_;  ///< [1/m] 1 / sigma_pos
  double w_yaw_;  ///< [1/rad] 1 / sigma_yaw
};

}  // namespace rgbdi::loop
