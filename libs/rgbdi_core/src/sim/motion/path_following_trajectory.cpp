#include "sim/motion/path_following_trajectory.h"

#include <cmath>

namespace rgbdi::sim {

MotionJet PathFollowingTrajectory::jetAt(double t) const {
  const Taylor<3> time = Taylor<3>::variable(t);
  const Taylor<3> s = motion_.speed.integral(time);
  const Taylor<3> envelope = motion_.speed.value(time) * (1.0 / motion_.cruise_speed);
  GroundPoint ground;
  if (motion_.path_start_m == 0.0 && !motion_.path_reverse) {
    ground = path_.at(s);
  } else if (!motion_.path_reverse) {
    ground = path_.at(motion_.path_start_m + s);
  } else {
    ground = path_.at(motion_.path_start_m - s);
    ground.heading = ground.heading + M_PI;
    ground.slope = -ground.slope;
  }
  // Uphill (positive slope) lifts the nose: a negative rotation about the body y axis.
  const Taylor<3> slope_pitch = -atan(ground.slope);

  TaylorVec3<3> offset;
  for (size_t i = 0; i < 3; ++i) offset[i] = envelope * motion_.translation[i].at(time);
  offset[2] += motion_.mount_height;
  offset = rotateAboutAxis(2, ground.heading, rotateAboutAxis(1, slope_pitch, offset));

  MotionJet jet;
  jet.position = ground.position + offset;
  jet.rotate(2, ground.heading.truncated<2>());
  jet.rotate(1, slope_pitch.truncated<2>());
  const Taylor<2> env = envelope.truncated<2>();
  const Taylor<2> time2 = time.truncated<2>();
  jet.rotate(2, env * motion_.rotation[2].at(time2));
  jet.rotate(1, motion_.pitch_bias + env * motion_.rotation[1].at(time2));
  jet.rotate(0, env * motion_.rotation[0].at(time2));
  return jet;
}

}  // namespace rgbdi::sim
