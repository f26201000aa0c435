#include "estimator/wheel_dead_reckoning.h"

#include <cmath>

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {
namespace {

/// Orientation of the body at time `t` from the gyroscope, integrated from (t0, q0) over the
/// samples (each sample's rate held until the next one).
class GyroOrientation {
 public:
  GyroOrientation(const std::vector<ImuSample>& imu, const Eigen::Vector3d& bg, double t0,
                  const Eigen::Quaterniond& q0)
      : imu_(imu), bg_(bg), t_(t0), q_(q0) {}
  /// Times must not decrease from call to call.
  Eigen::Quaterniond at(double t) {
    while (t_ < t) {
      while (next_ < imu_.size() && imu_[next_].t <= t_) ++next_;
      const std::size_t k = next_ == 0 ? 0 : next_ - 1;
      const double t_end = next_ < imu_.size() ? std::min(t, imu_[next_].t) : t;
      if (!imu_.empty()) q_ = (q_ * expQuat((imu_[k].gyr - bg_) * (t_end - t_))).normalized();
      t_ = t_end;
    }
    return q_;
  }

 private:
  const std::vector<ImuSample>& imu_;
  Eigen::Vector3d bg_;
  double t_;
  Eigen::Quaterniond q_;
  std::size_t next_ = 0;
};

}  // namespace

std::optional<DeadReckoning> wheelInertialDeadReckoning(const WindowWheels& wheels,
                                                        const WheelOptions& opt,
                                                        const std::vector<ImuSample>& imu,
                                                        const Eigen::Vector3d& bg, double t0,
                                                        const Eigen::Vector3d& p0,
                                                        const Eigen::Quaterniond& q0, double t) {
  const auto& r = wheels.readings;
  const auto stamp = [&](std::size_t i) { return r[i].t + wheels.time_offset[0]; };
  if (r.empty() || !(t >= t0) || stamp(0) > t0 || stamp(r.size() - 1) < t - opt.reading_lag_s)
    return std::nullopt;
  const Eigen::Isometry3d T_bw = wheels.T_body_wheel(opt);
  const Eigen::Matrix3d R_bw = T_bw.rotation();
  const Eigen::Vector3d p_bw = T_bw.translation();
  GyroOrientation orientation(imu, bg, t0, q0);
  Eigen::Vector3d p_wheel = p0 + q0 * p_bw;
  const double s_v = wheels.scale_v[0];
  Eigen::Vector3d v_wheel_world = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i + 1 < r.size(); ++i) {
    const double a = stamp(i), b = stamp(i + 1);
    if (b <= t0 || a >= t || b <= a) continue;
    // The part of increment i inside [t0, t], as a fraction of it (odometry is smooth
    // between readings).
    const double lo = std::max(a, t0), hi = std::min(b, t);
    const double f = (hi - lo) / (b - a);
    const double yaw = r[i].yaw_rad;
    const Eigen::Vector2d d_odo(r[i + 1].x_m - r[i].x_m, r[i + 1].y_m - r[i].y_m);
    const Eigen::Vector2d d_local = Eigen::Rotation2Dd(-yaw) * d_odo;  // in the wheel frame
    const Eigen::Vector3d step(s_v * f * d_local.x(), s_v * f * d_local.y(), 0.0);
    const Eigen::Quaterniond q_mid = orientation.at(0.5 * (lo + hi));
    const Eigen::Vector3d world_step = q_mid * (R_bw * step);
    p_wheel += world_step;
    if (hi > lo) v_wheel_world = world_step / (hi - lo);
  }
  // The newest reading may be a little older than t: the last increment's velocity goes on.
  const double t_last = std::max(t0, stamp(r.size() - 1));
  if (t > t_last) p_wheel += v_wheel_world * (t - t_last);
  const Eigen::Quaterniond q_t = orientation.at(t);
  DeadReckoning out;
  out.p_world_body = p_wheel - q_t * p_bw;
  out.v_world = v_wheel_world;
  return out;
}

}  // namespace rgbdi::estimator
