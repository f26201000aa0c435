// Sliding the window after an update (doc/estimator.md "Marginalisation"). When the
// second-newest frame is a keyframe, the oldest frame, its IMU factor and the tracks anchored in
// it are marginalised into the prior (Schur complement, marginalization.h); otherwise the
// second-newest frame's visual measurements are dropped, its IMU interval is merged into the
// next one and its pose is marginalised out of the prior if the prior holds it.
#pragma once

#include "estimator/window_cost_model.h"
#include "rgbdi/estimator/sliding_window_estimator.h"

namespace rgbdi::estimator {

struct WindowState;

/// Marginalises the oldest slot and removes it; returns its state (of odometry segment
/// `segment`), final for the odometry.
KeyframeState marginaliseOldestSlot(WindowState& state, const WindowCostModel& model, int segment);

/// Removes the second-newest slot (no keyframe), marginalising its pose out of the prior.
void dropSecondNewestSlot(WindowState& state, const WindowCostModel& model);

}  // namespace rgbdi::estimator
