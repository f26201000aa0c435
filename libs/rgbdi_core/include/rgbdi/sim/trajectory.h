// Analytic body trajectories of the simulator and the kinematic state derived from them.
//
// A trajectory is written once as formulas of time in Taylor arithmetic (motion_taylor.h):
// the world position of the body (IMU) origin and R_world_body as a chain of rotations about
// coordinate axes. Velocity, acceleration, body angular rate and its derivative then follow
// exactly (to floating-point round-off, about 1e-12 relative), which is what makes the
// synthesised IMU consistent with the ground truth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstddef>

#include "rgbdi/sim/motion_taylor.h"

namespace rgbdi::sim {

/// One factor of the orientation chain: a rotation about body-frame coordinate axis `axis`
/// (0 = x, 1 = y, 2 = z) by `angle` [rad].
struct AxisRotation {
  int axis = 2;
  Taylor<2> angle;
};

/// The Taylor expansion of a trajectory at one instant: position to 3rd order,
/// R_world_body = R_0 * R_1 * ... * R_{n-1} with each angle to 2nd order.
struct MotionJet {
  static constexpr std::size_t kMaxRotations = 10;
  TaylorVec3<3> position;
  std::array<AxisRotation, kMaxRotations> rotations{};
  std::size_t rotation_count = 0;

  /// Appends a factor on the right of the chain (a rotation about the current body axis).
  void rotate(int axis, const Taylor<2>& angle);
};

/// The ground-truth kinematic state of the body (IMU) frame at one time.
struct KinematicState {
  double t = 0.0;                                                  ///< [s] since sequence start
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();  ///< pose
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();               ///< [m/s]
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();               ///< [m/s^2] (no gravity)
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();            ///< [rad/s] body angular rate
  Eigen::Vector3d omega_dot_body = Eigen::Vector3d::Zero();        ///< [rad/s^2]

  /// What an ideal accelerometer measures: R_world_body^T (a_world - g_world) with
  /// g_world = (0, 0, -gravity) (world z up).
  Eigen::Vector3d specificForce(double gravity) const;
};

/// Converts a jet into the kinematic state (rotations multiplied out, rates accumulated).
KinematicState stateFromJet(double t, const MotionJet& jet);

/// A smooth (position C3, angular rate C1 or better) analytic trajectory on [0, duration()].
class BodyTrajectory {
 public:
  virtual ~BodyTrajectory() = default;
  /// [s] total duration.
  virtual double duration() const = 0;

  /// The trajectory's expansion at time t [s] since the start, t clamped to [0, duration()]
  /// (every profile starts and ends at rest, so clamping continues it smoothly).
  MotionJet jet(double t) const { return jetAt(std::clamp(t, 0.0, duration())); }
  KinematicState state(double t) const { return stateFromJet(t, jet(t)); }
  Eigen::Isometry3d pose(double t) const { return state(t).T_world_body; }

 protected:
  virtual MotionJet jetAt(double t) const = 0;
};

}  // namespace rgbdi::sim
