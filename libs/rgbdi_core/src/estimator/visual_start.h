// Moving start without depth (VINS-Mono style; `--no-depth`, or frames with too little depth):
// once the window is full, an up-to-scale SfM over it (visual_sfm.h), then gyro bias, velocities,
// gravity and the metric scale from the IMU (scale_alignment.h). The window must be full: the
// scale is observable only from changes of acceleration, and a short window leaves it poorly
// determined; at constant speed it is not observable at all, and the start keeps waiting.
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Geometry>

#include "estimator/window_start.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"

namespace rgbdi::estimator {

class FrameWindow;

/// Solves the start over `window` once it is full (re-propagating its pre-integrations with the
/// solved gyro bias). `log`: the solved scale at info level.
MovingStart solveVisualStart(FrameWindow& window, const EstimatorOptions& opt,
                             const ImuOptions& imu, const Eigen::Isometry3d& T_body_cam,
                             mrpt::system::COutputLogger& log);

}  // namespace rgbdi::estimator
