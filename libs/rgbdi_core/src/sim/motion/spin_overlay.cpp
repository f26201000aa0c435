#include "sim/motion/spin_overlay.h"

#include <cmath>
#include <stdexcept>

namespace rgbdi::sim {

SpinOverlayTrajectory::SpinOverlayTrajectory(std::shared_ptr<const BodyTrajectory> base,
                                             double start_s, double duration_s, double turns)
    : base_(std::move(base)) {
  if (!base_) throw std::invalid_argument("SpinOverlayTrajectory: no base trajectory");
  if (!std::isfinite(start_s) || !std::isfinite(turns) || !(duration_s > 0.0) ||
      !std::isfinite(duration_s))
    throw std::invalid_argument(
        "SpinOverlayTrajectory: start and turns must be finite, duration positive");
  angle_.addStep(start_s, duration_s, 2.0 * M_PI * turns);
}

MotionJet SpinOverlayTrajectory::jetAt(double t) const {
  const MotionJet inner = base_->jet(t);
  if (inner.rotation_count >= MotionJet::kMaxRotations)
    throw std::logic_error("SpinOverlayTrajectory: the profile's rotation chain is full");
  // The turn about the world z axis is the first factor of the chain; the profile's factors
  // follow unchanged.
  MotionJet jet;
  jet.position = inner.position;
  jet.rotate(2, angle_.value(Taylor<2>::variable(t)));
  for (std::size_t i = 0; i < inner.rotation_count; ++i)
    jet.rotate(inner.rotations[i].axis, inner.rotations[i].angle);
  return jet;
}

}  // namespace rgbdi::sim
