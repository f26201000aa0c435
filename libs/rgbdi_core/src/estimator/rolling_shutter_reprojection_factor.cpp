#include "rgbdi/estimator/rolling_shutter_reprojection_factor.h"

namespace rgbdi::estimator {

RollingShutterReprojectionFactor::RollingShutterReprojectionFactor(
    const FeatureMeasurement& obs_i, const FeatureMeasurement& obs_j,
    const Eigen::Isometry3d& T_body_cam, double sqrt_info) {
  reset(obs_i, obs_j, T_body_cam, sqrt_info);
}

void RollingShutterReprojectionFactor::reset(const FeatureMeasurement& obs_i,
                                             const FeatureMeasurement& obs_j,
                                             const Eigen::Isometry3d& T_body_cam,
                                             double sqrt_info) {
  core_.reset(obs_i, obs_j, T_body_cam, sqrt_info);
}

bool RollingShutterReprojectionFactor::Evaluate(double const* const* parameters, double* residuals,
                                                double** jacobians) const {
  const double td = parameters[3][0];
  const double readout = parameters[4][0];
  const FeatureMeasurement& i = core_.obsI();
  const FeatureMeasurement& j = core_.obsJ();
  // The time each observation is moved by: the offset's change and its row's share of the
  // readout's change since the observation was moved to the stamp. A unit of td moves both by
  // one; a unit of readout by their row fractions.
  const double dt_i = (td - i.td_at_stamp) + (readout - i.readout_at_stamp_s) * i.row_fraction;
  const double dt_j = (td - j.td_at_stamp) + (readout - j.readout_at_stamp_s) * j.row_fraction;
  const double shift_i[2] = {1.0, i.row_fraction};
  const double shift_j[2] = {1.0, j.row_fraction};
  core_.evaluate(parameters, dt_i, dt_j, residuals, jacobians, 2, shift_i, shift_j);
  return true;
}

}  // namespace rgbdi::estimator
