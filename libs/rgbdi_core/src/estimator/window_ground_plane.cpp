#include "estimator/window_ground_plane.h"

#include "rgbdi/estimator/ground_plane_gate.h"
#include "rgbdi/estimator/wheel_start.h"

namespace rgbdi::estimator {

void judgeNewFrames(WindowState& state, const imu::ImuBuffer& imu, const WheelOptions& opt,
                    double gravity_m_s2) {
  WindowWheels& wheels = state.wheels;
  for (WindowSlot& s : state.frames) {
    if (s.ground_judged) continue;
    const WheelCalibration calib = wheels.calibration(opt);
    const std::optional<Eigen::Vector3d> up =
        wheelInertialUp(wheels.readings, calib, imu, s.t, s.bg(), gravity_m_s2, opt);
    const double wheel_z = (s.T() * calib.T_body_wheel).translation().z();
    s.ground_z = judgeGroundContact(up, wheel_z, &wheels.ground, opt);
    s.ground_judged = true;
  }
}

}  // namespace rgbdi::estimator
