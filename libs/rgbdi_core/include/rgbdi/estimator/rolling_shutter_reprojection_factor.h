// Reprojection residual with the rolling-shutter readout time as a parameter (online estimation
// of the readout, [estimator] estimate_rolling_shutter_readout).
//
// The same residual as ReprojectionFactor, with the observation shift of VINS-Mono's
//   pts - (td - td_i + TR / ROW * row_i) * velocity
// in the form the window keeps its observations in: xn was moved to the stamp at entry with the
// readout estimate of that time (readout_at_stamp_s), so the shift left is
//   xn - ((td - td_at_stamp) + (readout - readout_at_stamp_s) * row_fraction) * velocity.
// With readout = readout_at_stamp_s it is ReprojectionFactor's residual.
//
// Parameter blocks: pose_i [7], pose_j [7], inverse depth in frame i [1], td [1], readout [1].
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "rgbdi/estimator/reprojection_factor.h"

namespace rgbdi::estimator {

class RollingShutterReprojectionFactor final : public ceres::SizedCostFunction<2, 7, 7, 1, 1, 1> {
 public:
  /// sqrt_info: 1 / sigma on the normalised plane (e.g. 460 / 1.5).
  RollingShutterReprojectionFactor(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
                                   const Eigen::Isometry3d& T_body_cam, double sqrt_info);
  /// Makes it the factor the constructor would make from these arguments (factors are reused).
  void reset(const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
             const Eigen::Isometry3d& T_body_cam, double sqrt_info);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  ShiftedReprojection core_;
};

}  // namespace rgbdi::estimator
