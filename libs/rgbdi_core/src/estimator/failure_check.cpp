#include "estimator/failure_check.h"

#include <cmath>

#include "estimator/frame_window.h"

namespace rgbdi::estimator {

const char* failureReason(const FrameWindow& window, const Eigen::Vector3d& prev_p, double prev_t,
                          const EstimatorOptions& opt) {
  const WindowSlot& s = window.back();
  if (s.ba().norm() > opt.fail_max_acc_bias_m_s2) return "accelerometer bias too large";
  if (s.bg().norm() > opt.fail_max_gyr_bias_rad_s) return "gyro bias too large";
  const Eigen::Vector3d jump = s.p() - prev_p;
  if (jump.norm() > opt.fail_max_jump_m) return "position jump";
  if (s.v().norm() > opt.fail_max_speed_m_s) return "speed too high";
  const double dt = s.t - prev_t;
  if (dt > 0.0 && jump.norm() > opt.fail_max_speed_m_s * dt)
    return "implausible motion between updates";
  if (std::abs(jump.z()) > opt.fail_max_vertical_jump_m) return "vertical jump";
  for (const auto& w : window)
    if (!w.p().allFinite() || !w.q().coeffs().allFinite()) return "non-finite state";
  return nullptr;
}

}  // namespace rgbdi::estimator
