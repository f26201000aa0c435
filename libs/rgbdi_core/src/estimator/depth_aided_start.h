// Depth-aided moving start (paper section 4.2, doc/estimator.md "Initialisation"): consecutive
// frames are chained by PnP RANSAC on depth-backed points, so the relative poses are metric;
// once the window spans enough frames, time and parallax (or is full), the gyro bias comes from
// the visual rotations and one linear solve gives the velocities and gravity (initializer.h).
// The start is refused while IMU and camera disagree (alignment residual above its gate).
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Geometry>

#include "estimator/window_start.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"

namespace rgbdi::estimator {

class FrameWindow;

/// Whether the newest slot has enough depth-backed features for PnP (else the visual start).
bool newestSlotHasDepthForPnp(const FrameWindow& window, const EstimatorOptions& opt);

/// Chains the newest slot of `window` to the previous one by PnP (on failure the window restarts
/// at the newest slot, its observations stamped with time offset `td`) and solves the start
/// when the window qualifies. Re-propagates the window's pre-integrations with the solved gyro
/// bias. `log`: PnP failures at debug level.
MovingStart solveDepthAidedStart(FrameWindow& window, double td, const EstimatorOptions& opt,
                                 const ImuOptions& imu, const Eigen::Isometry3d& T_body_cam,
                                 mrpt::system::COutputLogger& log);

}  // namespace rgbdi::estimator
