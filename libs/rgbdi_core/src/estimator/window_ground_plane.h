// The ground plane's gate over the window (doc/wheels.md "Ground plane"): every frame not judged
// yet is judged (judgeGroundContact) on the wheel-inertial tilt at its time and its present
// height, in time order, and keeps that verdict (the plane's height, or none) while it is in the
// window.
#pragma once

#include "estimator/window_state.h"
#include "rgbdi/imu/imu_buffer.h"

namespace rgbdi::estimator {

void judgeNewFrames(WindowState& state, const imu::ImuBuffer& imu, const WheelOptions& opt,
                    double gravity_m_s2);

}  // namespace rgbdi::estimator
