// How a start becomes the window's first states: the world frame is the gravity-aligned frame
// whose origin and yaw continue the trajectory from before a reset (the anchor: the last good
// pose; the origin and yaw 0 at the first start), and what the start knows about the first
// state's speed and biases becomes its prior (StartPrior).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "estimator/static_start.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/wheel_start.h"

namespace rgbdi::estimator {

struct WindowState;

/// A moving start solved in a reference frame (the first camera's), or why there is none yet.
struct MovingStart {
  const char* failure = nullptr;              ///< why not (a string literal); null when solved
  std::vector<Eigen::Isometry3d> T_ref_body;  ///< every slot's metric body pose
  std::vector<Eigen::Vector3d> v_ref;         ///< [m/s] every slot's velocity
  Eigen::Vector3d g_ref = Eigen::Vector3d::Zero();  ///< [m/s^2] gravity
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();     ///< [rad/s] gyro bias

  static MovingStart failed(const char* why) {
    MovingStart s;
    s.failure = why;
    return s;
  }
};

/// Sets the single slot of the window at rest: attitude from the mean specific force, yaw `yaw0`
/// [rad], position `p0` [m], zero velocity, gyro bias the mean rate.
void adoptRestingStart(WindowState& state, const Stillness& still, const Eigen::Vector3d& p0,
                       double yaw0, const EstimatorOptions& opt);

/// Sets the single slot of the window from the wheels' start: attitude from its "up", yaw `yaw0`
/// [rad], position `p0` [m], its velocity and gyro bias; the velocity prior is
/// [wheel] start_velocity_sigma_m_s.
void adoptWheelStart(WindowState& state, const WheelStart& start, const Eigen::Vector3d& p0,
                     double yaw0, const EstimatorOptions& opt);

/// Sets every slot of the window from `start`: the oldest body at `p0` [m] with yaw `yaw0` [rad].
void adoptMovingStart(WindowState& state, const MovingStart& start, const Eigen::Vector3d& p0,
                      double yaw0, const EstimatorOptions& opt);

}  // namespace rgbdi::estimator
