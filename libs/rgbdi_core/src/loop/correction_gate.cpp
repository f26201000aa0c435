#include "rgbdi/loop/correction_gate.h"

#include <algorithm>
#include <cmath>

namespace rgbdi::loop {

LoopDisagreement loopDisagreement(const LoopConstraint& c, const Eigen::Isometry3d& T_from_to_odom,
                                  const CorrectionGateOptions& options) {
  LoopDisagreement d;
  const Eigen::Isometry3d E = T_from_to_odom.inverse() * c.T_from_to;
  d.position_m = E.translation().norm();
  d.yaw_deg = std::abs(std::atan2(E.linear()(1, 0), E.linear()(0, 0))) * 180.0 / M_PI;
  // The standard error of the mean offset of the verified 3-D pairs: what the loop's
  // translation is known to (its yaw follows the same points, at a lever of metres).
  d.sigma_position_m =
      std::max(options.sigma_floor_m, c.depth_rms_m / std::sqrt(std::max(1, c.depth_inliers)));
  d.sigma_yaw_deg = options.yaw_sigma_deg_per_m * d.sigma_position_m;
  d.sigmas = std::max(d.position_m / d.sigma_position_m, d.yaw_deg / d.sigma_yaw_deg);
  d.shows_drift = options.gate_sigma <= 0.0 || d.sigmas > options.gate_sigma;
  return d;
}

}  // namespace rgbdi::loop
