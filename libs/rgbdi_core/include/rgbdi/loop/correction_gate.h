// Whether a verified loop shows drift at all: a loop whose relative pose agrees with the
// odometry's within the loop's own uncertainty carries no evidence that the odometry needs
// correcting, and a pose graph that applies it only adds the loop's measurement error to a
// trajectory that was right (doc/loop.md, "Correction gate").
#pragma once

#include <Eigen/Geometry>

#include "rgbdi/loop/loop_verifier.h"

namespace rgbdi::loop {

struct CorrectionGateOptions {
  /// [sigma] the graph starts correcting the odometry with the first loop whose relative pose
  /// disagrees with the odometry's by more than this many of the loop's own sigmas (position or
  /// yaw); 0: every loop corrects
  double gate_sigma = 2.0;
  /// [m] floor of a loop's position sigma (depth RMS of its agreeing 3-D pairs / sqrt(count))
  double sigma_floor_m = 0.001;
  /// [deg/m] a loop's yaw sigma per metre of its position sigma
  double yaw_sigma_deg_per_m = 20.0;
};

struct LoopDisagreement {
  double position_m = 0.0;  ///< |translation| of T_odom^-1 T_loop
  double yaw_deg = 0.0;     ///< |yaw| of T_odom^-1 T_loop
  double sigma_position_m = 0.0;
  double sigma_yaw_deg = 0.0;
  double sigmas = 0.0;       ///< the larger of the two ratios
  bool shows_drift = false;  ///< sigmas > gate (always when the gate is 0)
};

/// The loop `c` (T_from_to measured) against the odometry's relative pose of the same two
/// keyframes, T_from_to_odom.
LoopDisagreement loopDisagreement(const LoopConstraint& c, const Eigen::Isometry3d& T_from_to_odom,
                                  const CorrectionGateOptions& options);

}  // namespace rgbdi::loop
