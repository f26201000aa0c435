// The gate of the soft ground-plane constraint (doc/wheels.md "Ground plane"): whether a window
// frame's wheel frame is on the floor's plane, judged once, when the frame is new, on evidence the
// constraint itself cannot bend: the tilt of the wheel frame against gravity from the wheels and
// the IMU over the last [wheel] start_window_s (wheelInertialUp: a ramp, a bump, a step tilts it
// whatever the window's states say), and the height of the frame's state (the IMU's prediction
// for the newest frame) above the plane. Judged on the window's solved attitude, a frame at a
// ramp's foot was pulled flat by the plane and passed, the next one predicted from it too, and
// the ramp was climbed short.
//
// Test: chi2 = |n x u|^2 / sigma_tilt^2 + ((z - z0) / sigma_z)^2, with n the wheel frame's up
// axis and u the wheel-inertial up (both in the body frame; |n x u| = sin of the tilt), z the
// wheel frame's height and z0 the plane's. Above ground_plane_gate_chi2 the frame is off the
// plane, and the plane ends there. The next frame whose tilt passes is on a plane again: the
// known plane nearest in height when its whole test passes there (the floor again after an
// up-and-down ramp, a bump, a platform left over a step: its drift held back to the floor's
// height), else a new one at its own height (the top of a ramp, a platform).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "rgbdi/estimator/wheel_options.h"

namespace rgbdi::estimator {

/// The floor's planes met so far (heights [m] in the world) and the present one.
struct GroundPlanes {
  std::optional<double> current;  ///< none: none yet, or it ended at a frame off the plane
  std::vector<double> known;      ///< every plane started, in the order met
};

/// The plane of the frame judged: its height [m] when the frame is on it, none when off.
/// `up_body`: the wheel-inertial up (none: unknown, the frame is off); `wheel_z` [m]: the wheel
/// frame's height; `planes`: updated. Needs ground_plane_sigma_m > 0.
std::optional<double> judgeGroundContact(const std::optional<Eigen::Vector3d>& up_body,
                                         double wheel_z, GroundPlanes* planes,
                                         const WheelOptions& opt);

}  // namespace rgbdi::estimator
