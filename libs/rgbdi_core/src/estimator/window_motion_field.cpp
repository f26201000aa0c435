#include "estimator/window_motion_field.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "estimator/frame_window.h"
#include "rgbdi/common/motion_field.h"
#include "rgbdi/imu/imu_buffer.h"

namespace rgbdi::estimator {

void assignMotionFieldVelocities(FrameWindow& window, std::size_t slot, const imu::ImuBuffer& imu,
                                 const Eigen::Isometry3d& T_body_cam) {
  const WindowSlot& s = window[slot];
  if (!imu.covers(s.t, s.t)) return;
  const Eigen::Vector3d w_b = imu.interpolate(s.t).gyr - s.bg();
  const CameraVelocity cam =
      cameraVelocity(T_body_cam, s.q().normalized().conjugate() * s.v(), w_b);
  const Eigen::Isometry3d T_c_w = (s.T() * T_body_cam).inverse();
  const int slot_i = static_cast<int>(slot);
  // Depth of each observation: measured, else from the track's estimate; features with neither
  // get the median of the others (the translational term only needs a rough depth).
  std::vector<std::pair<TrackObservation*, double>> todo;
  std::vector<double> known;
  for (auto& [id, f] : window.features().tracks()) {
    if (f.start_slot > slot_i || f.endSlot() < slot_i) continue;
    TrackObservation& o = f.obs[static_cast<std::size_t>(slot_i - f.start_slot)];
    double z = o.depth_m;
    if (!(z > 0.0) && f.hasDepth()) {
      const Eigen::Isometry3d T_w_ci =
          window[static_cast<std::size_t>(f.start_slot)].T() * T_body_cam;
      z = (T_c_w * (T_w_ci * (f.obs.front().meas.xn / f.inv_depth))).z();
    }
    if (z > 0.0) known.push_back(z);
    todo.emplace_back(&o, z);
  }
  const double typical = typicalDepth(std::move(known));
  for (auto& [o, z] : todo) {
    o->meas.velocity =
        motionFieldVelocity(o->meas.xn.head<2>(), z > 0.0 ? z : typical, cam.omega_cam, cam.v_cam);
    // The rolling-shutter shift along the better (IMU) velocity.
    o->compensateRollingShutter();
  }
}

}  // namespace rgbdi::estimator
