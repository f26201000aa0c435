// A fast turn about the world vertical added to a profile's trajectory: the simulator's
// "extreme rotation" (a robot spinning in place, a whip pan of a hand-held camera).
#pragma once

#include <memory>

#include "rgbdi/sim/motion_smooth_steps.h"
#include "rgbdi/sim/trajectory.h"

namespace rgbdi::sim {

/// R_world_body(t) = Rz(angle(t)) * R_profile(t), position unchanged. The angle rises by
/// 2 pi * turns between `start` and `start + duration` [s] along the degree-7 smoothstep, so
/// angular rate and acceleration stay continuous (the IMU stays consistent with the pose) and the
/// peak rate, at mid-turn, is 2 pi * turns * 35/16 / duration. After whole turns the profile goes
/// on as before; after a fraction of a turn it goes on looking in the turned direction.
class SpinOverlayTrajectory : public BodyTrajectory {
 public:
  /// Throws std::invalid_argument when duration is not positive or start, turns are not finite.
  SpinOverlayTrajectory(std::shared_ptr<const BodyTrajectory> base, double start_s,
                        double duration_s, double turns);
  double duration() const override { return base_->duration(); }

 protected:
  MotionJet jetAt(double t) const override;

 private:
  std::shared_ptr<const BodyTrajectory> base_;
  SmoothSteps angle_;  ///< [rad] of time [s]
};

}  // namespace rgbdi::sim
