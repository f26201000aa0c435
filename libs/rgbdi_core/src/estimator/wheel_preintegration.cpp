#include "rgbdi/estimator/wheel_preintegration.h"

#include <algorithm>
#include <cmath>

#include "rgbdi/common/so3.h"

namespace rgbdi::estimator {
namespace {

struct Pose2 {
  double x = 0.0, y = 0.0, yaw = 0.0;
};

Eigen::Matrix2d rot2(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

/// The pose of reading i with its yaw unwrapped against `ref` (readings wrap at +-pi).
Pose2 unwrapped(const WheelOdometrySample& w, double ref) {
  return {w.x_m, w.y_m, unwrappedYaw(w, ref)};
}

/// The wheel frame's rotation at increasing times relative to the start time, from the gyroscope
/// (each sample's rate held until the next one; the first one's before it).
class WheelFrameRotation {
 public:
  WheelFrameRotation(const WheelGyro& g, double t0) : g_(g), t_(t0) {}
  /// Times must not decrease from call to call.
  Eigen::Matrix3d at(double t) {
    const std::vector<ImuSample>& imu = *g_.samples;
    while (t_ < t && !imu.empty()) {
      while (next_ < imu.size() && imu[next_].t <= t_) ++next_;
      const std::size_t k = next_ == 0 ? 0 : next_ - 1;
      const double t_end = next_ < imu.size() ? std::min(t, imu[next_].t) : t;
      q_ = (q_ * expQuat((imu[k].gyr - g_.bias) * (t_end - t_))).normalized();
      t_ = t_end;
    }
    return g_.R_body_wheel.transpose() * q_.toRotationMatrix() * g_.R_body_wheel;
  }

 private:
  const WheelGyro& g_;
  double t_;
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
  std::size_t next_ = 0;
};

}  // namespace

WheelPreintegration::WheelPreintegration(std::vector<Eigen::Vector2d> d, std::vector<double> a,
                                         const WheelNoise& noise, std::vector<Eigen::Matrix3d> R)
    : d_(std::move(d)), R_(std::move(R)) {
  phi_.reserve(a.size());
  double phi = 0.0;
  for (std::size_t k = 0; k < d_.size(); ++k) {
    phi_.push_back(phi);
    phi += a[k];
    distance_ += d_[k].norm();
  }
  phi_end_ = phi;
  const auto sigma = [](double per, double amount, double floor) {
    return std::max(floor, per * std::sqrt(std::abs(amount)));
  };
  const double yaw_var = std::pow(noise.yaw_sigma_per_sqrt_rad, 2) * std::abs(phi_end_) +
                         std::pow(noise.yaw_sigma_per_sqrt_m, 2) * distance_;
  const double s_yaw = std::max(noise.min_sigma_rad, std::sqrt(yaw_var));
  const double s_tilt = sigma(noise.tilt_sigma_per_sqrt_m, distance_, noise.min_sigma_rad);
  sqrt_info_ << 1.0 / sigma(noise.forward_sigma_per_sqrt_m, distance_, noise.min_sigma_m),
      1.0 / sigma(noise.lateral_sigma_per_sqrt_m, distance_, noise.min_sigma_m),
      1.0 / sigma(noise.vertical_sigma_per_sqrt_m, distance_, noise.min_sigma_m), 1.0 / s_tilt,
      1.0 / s_tilt, 1.0 / s_yaw;
  // 3-D: the rotation is the IMU factor's (the wheels' yaw adds nothing to the gyroscope over
  // seconds and slips on tracks); the vertical keeps its loose sigma, as the gyroscope's tilt
  // drifts with its bias error (a 5 s blackout over a ramp early in a run: 3 cm too high with
  // the lateral sigma there, doc/wheels.md "Blind frames").
  if (threeD()) sqrt_info_.tail<3>().setZero();
}

std::optional<WheelPreintegration> WheelPreintegration::between(
    const std::deque<WheelOdometrySample>& readings, double t_a, double t_b, double time_offset_s,
    const WheelNoise& noise, double max_extrapolation_s, const WheelGyro* gyro) {
  const auto stamp = [&](std::size_t i) { return readings[i].t + time_offset_s; };
  if (readings.empty() || !(t_b >= t_a) || stamp(0) > t_a ||
      stamp(readings.size() - 1) < t_b - max_extrapolation_s)
    return std::nullopt;
  // i0: the last reading at or before t_a.
  std::size_t i0 = 0;
  while (i0 + 1 < readings.size() && stamp(i0 + 1) <= t_a) ++i0;
  std::vector<Pose2> poses;   // the poses at t_a, at every reading inside (t_a, t_b), at t_b
  std::vector<double> times;  // their IMU-clock times
  double ref = readings[i0].yaw_rad;
  const std::size_t last = readings.size() - 1;
  const auto at = [&](double t, std::size_t i) {  // between reading i and i + 1
    if (i == last && t > stamp(last) && last >= 1 && stamp(last) > stamp(last - 1)) {
      // Beyond the newest reading (by at most max_extrapolation_s): its increment's rate goes on.
      const Pose2 p = unwrapped(readings[last - 1], ref);
      const Pose2 q = unwrapped(readings[last], p.yaw);
      const double f = (t - stamp(last - 1)) / (stamp(last) - stamp(last - 1));
      return Pose2{p.x + f * (q.x - p.x), p.y + f * (q.y - p.y), p.yaw + f * (q.yaw - p.yaw)};
    }
    const Pose2 p = unwrapped(readings[i], ref);
    if (i + 1 >= readings.size() || stamp(i + 1) <= stamp(i)) return p;
    const Pose2 q = unwrapped(readings[i + 1], p.yaw);
    const double f = std::clamp((t - stamp(i)) / (stamp(i + 1) - stamp(i)), 0.0, 1.0);
    return Pose2{p.x + f * (q.x - p.x), p.y + f * (q.y - p.y), p.yaw + f * (q.yaw - p.yaw)};
  };
  poses.push_back(at(t_a, i0));
  times.push_back(t_a);
  std::size_t i = i0 + 1;
  for (; i < readings.size() && stamp(i) < t_b; ++i) {
    poses.push_back(unwrapped(readings[i], poses.back().yaw));
    times.push_back(stamp(i));
    ref = poses.back().yaw;
  }
  ref = poses.back().yaw;
  poses.push_back(at(t_b, i - 1));
  times.push_back(t_b);
  std::vector<Eigen::Vector2d> d;
  std::vector<double> a;
  std::vector<Eigen::Matrix3d> R;
  std::optional<WheelFrameRotation> rotation;
  if (gyro && gyro->samples) rotation.emplace(*gyro, t_a);
  for (std::size_t k = 1; k < poses.size(); ++k) {
    const Pose2& p = poses[k - 1];
    const Pose2& q = poses[k];
    d.push_back(rot2(-p.yaw) * Eigen::Vector2d(q.x - p.x, q.y - p.y));
    a.push_back(q.yaw - p.yaw);
    if (rotation) R.push_back(rotation->at(times[k - 1]));
  }
  WheelPreintegration out(std::move(d), std::move(a), noise, std::move(R));
  out.cut_time_offset_s_ = time_offset_s;
  // The slopes of the interpolation at the two cuts: the segment each one is interpolated in
  // (beyond the newest reading: the last one, whose rate goes on).
  const auto rateOf = [&](std::size_t seg, double yaw_at_cut, Eigen::Vector2d* v, double* w) {
    if (last == 0) return;
    seg = std::min(seg, last - 1);
    const double dt = stamp(seg + 1) - stamp(seg);
    if (!(dt > 0.0)) return;
    const Pose2 p = unwrapped(readings[seg], yaw_at_cut);
    const Pose2 q = unwrapped(readings[seg + 1], p.yaw);
    *v = rot2(-yaw_at_cut) * Eigen::Vector2d(q.x - p.x, q.y - p.y) / dt;
    *w = (q.yaw - p.yaw) / dt;
  };
  rateOf(i0, poses.front().yaw, &out.rates_.v_start, &out.rates_.w_start);
  rateOf(i - 1, poses.back().yaw, &out.rates_.v_end, &out.rates_.w_end);
  return out;
}

CalibratedWheelMotion WheelPreintegration::calibratedMotion(double s_v, double s_w, double yaw,
                                                            double dtd) const {
  CalibratedWheelMotion m;
  m.ddp_dyaw.setZero();
  m.ddp_dtd.setZero();
  if (threeD()) {
    // R_k(yaw) = Rz(-yaw) R_k0 Rz(yaw): the gyroscope's rotation seen in the corrected frame.
    const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
    Eigen::Vector3d S = Eigen::Vector3d::Zero(), dS = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < d_.size(); ++k) {
      const Eigen::Vector3d dk = Rz * Eigen::Vector3d(d_[k].x(), d_[k].y(), 0.0);
      S += R_[k] * dk;
      dS += R_[k] * ez.cross(dk);
    }
    const Eigen::Vector3d u = Rz.transpose() * S;
    m.dp = s_v * u;
    m.ddp_dsv = u;
    m.ddp_dsw.setZero();
    m.ddp_dyaw = s_v * (-ez.cross(u) + Rz.transpose() * dS);
    m.dyaw = s_w * phi_end_;
    m.ddyaw_dsw = phi_end_;
    return m;
  }
  // Planar: dp = s_v (p1 + dtd c1), c1 = v_a + s_w w_a J p1 - R(s_w phi_n) v_b, p1 = dp / s_v.
  Eigen::Vector2d p1, dp1_dsw;
  delta(1.0, s_w, &p1, nullptr, &dp1_dsw);
  const Eigen::Matrix2d J = (Eigen::Matrix2d() << 0.0, -1.0, 1.0, 0.0).finished();
  const WheelCutRates& r = rates_;
  const Eigen::Matrix2d Rn = rot2(s_w * phi_end_);
  const Eigen::Vector2d c1 = r.v_start + s_w * r.w_start * (J * p1) - Rn * r.v_end;
  const Eigen::Vector2d dc1_dsw =
      r.w_start * (J * p1) + s_w * r.w_start * (J * dp1_dsw) - phi_end_ * (J * Rn * r.v_end);
  const auto lift = [](const Eigen::Vector2d& v) { return Eigen::Vector3d(v.x(), v.y(), 0.0); };
  m.dp = lift(s_v * (p1 + dtd * c1));
  m.ddp_dsv = lift(p1 + dtd * c1);
  m.ddp_dsw = lift(s_v * (dp1_dsw + dtd * dc1_dsw));
  m.ddp_dtd = lift(s_v * c1);
  const double dw = r.w_start - r.w_end;
  m.dyaw = s_w * (phi_end_ + dtd * dw);
  m.ddyaw_dsw = phi_end_ + dtd * dw;
  m.ddyaw_dtd = s_w * dw;
  return m;
}

void WheelPreintegration::motion(double s_v, double s_w, Eigen::Vector3d* dp, double* dyaw,
                                 Eigen::Vector3d* ddp_dsw) const {
  if (threeD()) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < d_.size(); ++k)
      p += R_[k] * Eigen::Vector3d(d_[k].x(), d_[k].y(), 0.0);
    if (dp) *dp = s_v * p;
    if (dyaw) *dyaw = s_w * phi_end_;
    if (ddp_dsw) ddp_dsw->setZero();
    return;
  }
  Eigen::Vector2d p2, dp2_dsw;
  delta(s_v, s_w, &p2, dyaw, &dp2_dsw);
  if (dp) *dp = Eigen::Vector3d(p2.x(), p2.y(), 0.0);
  if (ddp_dsw) *ddp_dsw = Eigen::Vector3d(dp2_dsw.x(), dp2_dsw.y(), 0.0);
}

void WheelPreintegration::delta(double s_v, double s_w, Eigen::Vector2d* dp, double* dyaw,
                                Eigen::Vector2d* ddp_dsw) const {
  if (threeD()) {
    Eigen::Vector3d p, dp_dsw;
    motion(s_v, s_w, &p, dyaw, &dp_dsw);
    if (dp) *dp = p.head<2>();
    if (ddp_dsw) *ddp_dsw = dp_dsw.head<2>();
    return;
  }
  Eigen::Vector2d p = Eigen::Vector2d::Zero(), dp_dsw = Eigen::Vector2d::Zero();
  const Eigen::Matrix2d J = (Eigen::Matrix2d() << 0.0, -1.0, 1.0, 0.0).finished();  // d R / da
  for (std::size_t k = 0; k < d_.size(); ++k) {
    const Eigen::Vector2d r = rot2(s_w * phi_[k]) * d_[k];
    p += r;
    dp_dsw += phi_[k] * (J * r);
  }
  if (dp) *dp = s_v * p;
  if (dyaw) *dyaw = s_w * phi_end_;
  if (ddp_dsw) *ddp_dsw = s_v * dp_dsw;
}

}  // namespace rgbdi::estimator
