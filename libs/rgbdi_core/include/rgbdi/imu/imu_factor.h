// Ceres cost function of one pre-integrated IMU interval between body states i and j.
//
// Parameter blocks: pose_i (7), speed_bias_i (9), pose_j (7), speed_bias_j (9).
//   pose       = [px, py, pz, qx, qy, qz, qw]  (T_world_body, Eigen quaternion coefficient order)
//   speed_bias = [vx, vy, vz, bax, bay, baz, bgx, bgy, bgz]  (velocity in world)
// Residual (15) = U * [r_p, r_theta, r_v, r_ba, r_bg] with U = Preintegration::sqrtInformation()
// and r as in Preintegration::residual (r_theta = Log(...)).
// Jacobians w.r.t. a pose block have 7 columns: the first 6 are the derivative w.r.t. the tangent
// perturbation [dp, dtheta] (p <- p + dp, q <- q * Exp(dtheta)), the 7th is zero; this matches a
// pose manifold whose PlusJacobian is [I6; 0].
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <cstdint>

#include "rgbdi/imu/preintegration.h"

namespace rgbdi::imu {

constexpr int kPoseBlockSize = 7;
constexpr int kSpeedBiasBlockSize = 9;

class ImuFactor : public ceres::SizedCostFunction<15, kPoseBlockSize, kSpeedBiasBlockSize,
                                                  kPoseBlockSize, kSpeedBiasBlockSize> {
 public:
  /// `preintegration` is not owned and must outlive the factor and must not change during a
  /// solve; it may be repropagated between solves. The square-root information is computed here
  /// and recomputed (without caching) by evaluations that find the pre-integration changed since.
  /// Throws std::invalid_argument when it is null, std::runtime_error when its covariance is not
  /// positive definite.
  ImuFactor(const Preintegration* preintegration, const Eigen::Vector3d& g_w);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const Preintegration* preintegration() const { return preint_; }
  const Eigen::Vector3d& gravity() const { return g_w_; }

 private:
  const Preintegration* preint_;
  Eigen::Vector3d g_w_;
  std::uint64_t info_revision_;  ///< revision of *preint_ that sqrt_info_ was computed from
  Matrix15d sqrt_info_;
};

}  // namespace rgbdi::imu
