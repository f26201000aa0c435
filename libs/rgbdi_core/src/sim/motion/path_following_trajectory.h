// The one trajectory model behind every simulator profile: a body carried along a GroundPath
// with a smooth speed profile, riding at a fixed height above the (smoothed) ground and pitched
// with its slope, plus oscillations that stand for walking, hand motion, track vibration and
// jitter. All oscillations are scaled by speed / cruise speed, so they vanish at rest and
// follow the speed smoothly.
#pragma once

#include <array>

#include "rgbdi/sim/motion_ground_path.h"
#include "rgbdi/sim/motion_smooth_steps.h"
#include "rgbdi/sim/trajectory.h"
#include "sim/motion/tones.h"

namespace rgbdi::sim {

struct PathFollowingMotion {
  SmoothSteps speed;          ///< v(t) [m/s] along the path (horizontal arc-length rate)
  double cruise_speed = 1.0;  ///< [m/s] speed at which the oscillations have their nominal size
  double duration = 0.0;      ///< [s]
  double mount_height = 0.0;  ///< [m] body origin above the ground, along the chassis z axis
  /// Oscillating displacement [m] in the chassis frame (x along the path, y left, z up).
  std::array<ToneSum, 3> translation;
  /// Oscillating roll (about x), pitch (about y) and yaw (about z) [rad] applied after the
  /// chassis orientation as Rz(yaw) Ry(pitch) Rx(roll).
  std::array<ToneSum, 3> rotation;
  double pitch_bias = 0.0;  ///< [rad] constant pitch of the body on the chassis (e.g. hand tilt)
  /// [m] arc length of the path where the motion starts (profile variants); the body is at
  /// path arc length path_start_m + s(t), or path_start_m - s(t) when path_reverse (driving the
  /// path backwards: heading turned by pi, slopes negated).
  double path_start_m = 0.0;
  bool path_reverse = false;
};

class PathFollowingTrajectory : public BodyTrajectory {
 public:
  PathFollowingTrajectory(GroundPath path, PathFollowingMotion motion)
      : path_(std::move(path)), motion_(std::move(motion)) {}

  double duration() const override { return motion_.duration; }
  const GroundPath& path() const { return path_; }
  const PathFollowingMotion& motion() const { return motion_; }

 protected:
  MotionJet jetAt(double t) const override;

 private:
  GroundPath path_;
  PathFollowingMotion motion_;
};

}  // namespace rgbdi::sim
