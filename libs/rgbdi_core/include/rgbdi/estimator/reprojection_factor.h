// Reprojection residual of a feature observed in frames i (its reference frame, where its inverse
// depth lives) and j, on the normalised image plane, with the camera-IMU time offset correction of
// VINS: an observation taken while the feature moved with image velocity v is shifted by
// -(td - td_at_stamping) * v, so td is observable from feature motion.
//
// Parameter blocks: pose_i [7], pose_j [7], inverse depth in frame i [1], td [1].
// The camera-IMU extrinsic T_body_cam is fixed (calibrated offline).
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rgbdi::estimator {

struct FeatureMeasurement {
  Eigen::Vector3d xn;        ///< undistorted normalised point (x, y, 1)
  Eigen::Vector2d velocity;  ///< d(xn)/dt [1/s]
  double td_at_stamp = 0.0;  ///< time offset used when this frame was stamped [s]
  /// Rolling shutter (read by RollingShutterReprojectionFactor only): the row's share of the
  /// readout (RollingShutter::rowFraction) and the readout xn was moved to the stamp with.
  double row_fraction = 0.0;        ///< [unitless]
  double readout_at_stamp_s = 0.0;  ///< [s]
};

/// What ReprojectionFactor and RollingShutterReprojectionFactor share: the two observations, the
/// extrinsic and the weight, and the residual with its analytic Jacobians once each observation
/// is shifted along its image velocity by its own time (dt_i, dt_j).
class ShiftedReprojection {
 public:
  void reset(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
             const Eigen::Isometry3d& T_body_cam, double sqrt_info);
  const FeatureMeasurement& obsI() const { return obs_i_; }
  const FeatureMeasurement& obsJ() const { return obs_j_; }

  /// parameters[0..2]: pose_i, pose_j, inverse depth. Jacobians (where jacobians[k] is given):
  /// k = 0..2 of those blocks; k = 3 + s for each of the `shifts` time parameters, a unit of which
  /// moves observation i by shift_i[s] and observation j by shift_j[s] of their dt.
  void evaluate(double const* const* parameters, double dt_i, double dt_j, double* residuals,
                double** jacobians, int shifts, const double* shift_i, const double* shift_j) const;

 private:
  FeatureMeasurement obs_i_, obs_j_;
  Eigen::Matrix3d R_bc_;
  Eigen::Vector3d t_bc_;
  double sqrt_info_ = 0.0;
};

class ReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 7, 1, 1> {
 public:
  /// sqrt_info: 1 / sigma on the normalised plane (e.g. 460 / 1.5).
  ReprojectionFactor(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
                     const Eigen::Isometry3d& T_body_cam, double sqrt_info);
  /// Makes it the factor the constructor would make from these arguments (a factor reused from
  /// one window update to the next: a thousand fresh ones per update cost allocations).
  void reset(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
             const Eigen::Isometry3d& T_body_cam, double sqrt_info);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  ShiftedReprojection core_;
};

}  // namespace rgbdi::estimator
