// Failure detection after an update (doc/estimator.md "Failure detection and recovery"): bias
// limits, position jumps, speeds beyond what the robot can do, non-finite states. A failure
// resets the estimator.
#pragma once

#include <Eigen/Core>

#include "rgbdi/estimator/estimator_options.h"

namespace rgbdi::estimator {

class FrameWindow;

/// Why the window's newest state is implausible, or null when it is not. `prev_p`, `prev_t`: the
/// newest slot's position and IMU-clock time after the previous update [m, s].
const char* failureReason(const FrameWindow& window, const Eigen::Vector3d& prev_p, double prev_t,
                          const EstimatorOptions& opt);

}  // namespace rgbdi::estimator
