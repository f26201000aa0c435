#include "rgbdi/estimator/wheel_start.h"

#include <cmath>

#include "rgbdi/common/so3.h"
#include "rgbdi/imu/imu_buffer.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {
namespace {

/// The odometry's planar pose, its yaw unwrapped.
struct OdoPose {
  double t, x, y, yaw;
};

/// The readings as poses on the IMU clock, yaw unwrapped from the first one.
std::vector<OdoPose> odometryOnImuClock(const std::deque<WheelOdometrySample>& readings,
                                        double time_offset_s) {
  std::vector<OdoPose> out;
  out.reserve(readings.size());
  for (const WheelOdometrySample& r : readings) {
    const double yaw = out.empty() ? r.yaw_rad : unwrappedYaw(r, out.back().yaw);
    out.push_back({r.t + time_offset_s, r.x_m, r.y_m, yaw});
  }
  return out;
}

/// The pose at time tau, linear between the readings around it (covered: checked by the caller).
OdoPose poseAt(const std::vector<OdoPose>& odo, double tau) {
  std::size_t i = 0;
  while (i + 2 < odo.size() && odo[i + 1].t <= tau) ++i;
  const OdoPose& a = odo[i];
  const OdoPose& b = odo[i + 1];
  const double f = b.t > a.t ? (tau - a.t) / (b.t - a.t) : 0.0;
  return {tau, a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.yaw + f * (b.yaw - a.yaw)};
}

/// Pre-integration of the IMU over [t0, t1] with gyroscope bias bg (accelerometer bias 0).
imu::Preintegration integrate(const imu::ImuBuffer& imu, double t0, double t1,
                              const Eigen::Vector3d& bg) {
  imu::Preintegration pre(Eigen::Vector3d::Zero(), bg, imu::ImuNoise{});
  for (const ImuSample& m : imu.between(t0, t1)) pre.push(m);
  return pre;
}

/// Mean gyro rate over [t0, t1] (trapezoid).
Eigen::Vector3d meanRate(const imu::ImuBuffer& imu, double t0, double t1) {
  const std::vector<ImuSample> s = imu.between(t0, t1);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k + 1 < s.size(); ++k)
    sum += 0.5 * (s[k].gyr + s[k + 1].gyr) * (s[k + 1].t - s[k].t);
  return sum / (t1 - t0);
}

/// The window [t_e - W, t_e] of a wheel-inertial estimate at IMU-clock time t, or why none.
struct WheelInertialWindow {
  const char* failure = nullptr;
  std::vector<OdoPose> odo;
  double h = 0.0;                          ///< [s] the velocity spans
  double t_a = 0.0, t_b = 0.0, t_c = 0.0;  ///< [s] their midpoints: first, last, middle
};

WheelInertialWindow makeWindow(const std::deque<WheelOdometrySample>& readings,
                               const imu::ImuBuffer& imu, double t, double time_offset_s,
                               const WheelOptions& opt) {
  WheelInertialWindow w;
  w.odo = odometryOnImuClock(readings, time_offset_s);
  if (w.odo.size() < 2) {
    w.failure = "no wheel readings";
    return w;
  }
  // The window ends at the newest reading (readings come at their own rate).
  const double W = opt.start_window_s;
  const double t_e = std::min(t, w.odo.back().t);
  if (t - t_e > opt.reading_lag_s)
    w.failure = "the wheel readings lag the frame";
  else if (w.odo.front().t > t_e - W)
    w.failure = "wheel readings shorter than the window";
  else if (imu.empty() || !imu.covers(t_e - W, t))
    w.failure = "IMU samples shorter than the window";
  w.h = 0.25 * W;  // the velocity spans: short against W, long against the ticks
  w.t_a = t_e - W + 0.5 * w.h;
  w.t_b = t_e - 0.5 * w.h;
  w.t_c = 0.5 * (w.t_a + w.t_b);
  return w;
}

/// The body velocity (body frame) at the middle of the span of length h centred on tau.
Eigen::Vector3d bodyVelocity(const WheelInertialWindow& w, const imu::ImuBuffer& imu, double tau,
                             const Eigen::Vector3d& bg, const WheelCalibration& calib) {
  const OdoPose p0 = poseAt(w.odo, tau - 0.5 * w.h), p1 = poseAt(w.odo, tau + 0.5 * w.h);
  const Eigen::Vector2d d_local =
      Eigen::Rotation2Dd(-0.5 * (p0.yaw + p1.yaw)) * Eigen::Vector2d(p1.x - p0.x, p1.y - p0.y);
  const Eigen::Vector3d v_wheel(calib.scale_v * d_local.x() / w.h,
                                calib.scale_v * d_local.y() / w.h, 0.0);
  const Eigen::Vector3d omega = meanRate(imu, tau - 0.5 * w.h, tau + 0.5 * w.h) - bg;
  return calib.T_body_wheel.rotation() * v_wheel - omega.cross(calib.T_body_wheel.translation());
}

/// Gravity in the body frame at t0 from the body velocities v0 at t0 and v1 at t1 (body frames);
/// R01: the body at t1 in the body at t0.
Eigen::Vector3d gravityBetween(const imu::ImuBuffer& imu, double t0, double t1,
                               const Eigen::Vector3d& v0, const Eigen::Vector3d& v1,
                               const Eigen::Vector3d& bg, Eigen::Matrix3d* R01) {
  const imu::Preintegration pre = integrate(imu, t0, t1, bg);
  *R01 = pre.deltaQ().toRotationMatrix();
  return (*R01 * v1 - v0 - pre.deltaV()) / (t1 - t0);
}

}  // namespace

WheelStart solveWheelStart(const std::deque<WheelOdometrySample>& readings,
                           const WheelCalibration& calib, const imu::ImuBuffer& imu, double t,
                           double gravity_m_s2, const WheelOptions& opt) {
  const WheelInertialWindow w = makeWindow(readings, imu, t, calib.time_offset_s, opt);
  if (w.failure) return WheelStart::failed(w.failure);
  // Gyroscope bias: the rate the wheels' yaw rate does not explain.
  const OdoPose pa = poseAt(w.odo, w.t_a), pb = poseAt(w.odo, w.t_b);
  const double wheel_yaw_rate = calib.scale_w * (pb.yaw - pa.yaw) / (w.t_b - w.t_a);
  const Eigen::Vector3d bg = meanRate(imu, w.t_a, w.t_b) -
                             calib.T_body_wheel.rotation() * Eigen::Vector3d(0, 0, wheel_yaw_rate);
  if (bg.norm() > opt.start_max_rate_dev_rad_s)
    return WheelStart::failed("gyro rate and the wheels' yaw rate disagree");
  const Eigen::Vector3d v_a = bodyVelocity(w, imu, w.t_a, bg, calib);
  const Eigen::Vector3d v_c = bodyVelocity(w, imu, w.t_c, bg, calib);
  const Eigen::Vector3d v_b = bodyVelocity(w, imu, w.t_b, bg, calib);
  Eigen::Matrix3d R_ac, R_cb, R_ab;
  const Eigen::Vector3d g_first = gravityBetween(imu, w.t_a, w.t_c, v_a, v_c, bg, &R_ac);
  const Eigen::Vector3d g_second = R_ac * gravityBetween(imu, w.t_c, w.t_b, v_c, v_b, bg, &R_cb);
  const Eigen::Vector3d g_a = gravityBetween(imu, w.t_a, w.t_b, v_a, v_b, bg, &R_ab);
  if ((g_first - g_second).norm() > opt.start_max_gravity_dev_m_s2)
    return WheelStart::failed("gravity from the two halves of the window disagrees");
  if (std::abs(g_a.norm() - gravity_m_s2) > opt.start_max_gravity_dev_m_s2)
    return WheelStart::failed("|gravity| from the wheels and the IMU differs from g");
  // From b to the frame by the IMU: v_t = v_b + g (t - t_b) + dv, in the body frame at t.
  const imu::Preintegration to_t = integrate(imu, w.t_b, t, bg);
  const Eigen::Matrix3d R_bt = to_t.deltaQ().toRotationMatrix();
  const Eigen::Vector3d g_b = R_ab.transpose() * g_a;
  WheelStart out;
  out.up_body = -(R_bt.transpose() * g_b);
  out.v_body = R_bt.transpose() * (v_b + g_b * (t - w.t_b) + to_t.deltaV());
  out.bg = bg;
  return out;
}

std::optional<Eigen::Vector3d> wheelInertialUp(const std::deque<WheelOdometrySample>& readings,
                                               const WheelCalibration& calib,
                                               const imu::ImuBuffer& imu, double t,
                                               const Eigen::Vector3d& bg, double gravity_m_s2,
                                               const WheelOptions& opt) {
  const WheelInertialWindow w = makeWindow(readings, imu, t, calib.time_offset_s, opt);
  if (w.failure) return std::nullopt;
  const Eigen::Vector3d v_a = bodyVelocity(w, imu, w.t_a, bg, calib);
  const Eigen::Vector3d v_b = bodyVelocity(w, imu, w.t_b, bg, calib);
  Eigen::Matrix3d R_ab;
  const Eigen::Vector3d g_a = gravityBetween(imu, w.t_a, w.t_b, v_a, v_b, bg, &R_ab);
  if (std::abs(g_a.norm() - gravity_m_s2) > opt.start_max_gravity_dev_m_s2) return std::nullopt;
  const Eigen::Matrix3d R_bt = integrate(imu, w.t_b, t, bg).deltaQ().toRotationMatrix();
  return Eigen::Vector3d(-(R_bt.transpose() * R_ab.transpose() * g_a));
}

}  // namespace rgbdi::estimator
