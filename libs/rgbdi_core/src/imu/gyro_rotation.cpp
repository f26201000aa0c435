#include "rgbdi/imu/gyro_rotation.h"

#include <algorithm>

#include "rgbdi/common/so3.h"

namespace rgbdi::imu {

namespace {
/// Calls step(gyr, acc, dt) for the pieces of [t0, t1] in time order: the oldest sample held
/// before the buffered span, the mean of consecutive samples inside it, the newest held after.
template <class Step>
void forEachPiece(const ImuBuffer& buffer, double t0, double t1, Step&& step) {
  if (buffer.empty() || !(t1 > t0)) return;
  const double oldest = buffer.oldestTime(), newest = buffer.newestTime();
  const ImuSample& first = buffer.samples().front();
  const ImuSample& last = buffer.samples().back();
  const double before_end = std::min(t1, oldest);
  if (before_end > t0) step(first.gyr, first.acc, before_end - t0);
  const double a = std::max(t0, oldest), b = std::min(t1, newest);
  if (b > a) {
    const std::vector<ImuSample> s = buffer.between(a, b);
    for (std::size_t k = 0; k + 1 < s.size(); ++k)
      step(0.5 * (s[k].gyr + s[k + 1].gyr), 0.5 * (s[k].acc + s[k + 1].acc), s[k + 1].t - s[k].t);
  }
  const double after_start = std::max(t0, newest);
  if (t1 > after_start) step(last.gyr, last.acc, t1 - after_start);
}
}  // namespace

Eigen::Quaterniond gyroRotation(const ImuBuffer& buffer, double t0, double t1,
                                const Eigen::Vector3d& bias_gyr) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  forEachPiece(buffer, t0, t1, [&](const Eigen::Vector3d& gyr, const Eigen::Vector3d&, double dt) {
    q = q * expQuat((gyr - bias_gyr) * dt);
  });
  return q.normalized();
}

Eigen::Isometry3d deadReckonedMotion(const ImuBuffer& buffer, double t0, double t1,
                                     const BodyState& start, const Eigen::Vector3d& g_world,
                                     BodyState* end) {
  Eigen::Quaterniond q = start.q_world_body.normalized();
  Eigen::Vector3d v = start.v_world, p = Eigen::Vector3d::Zero();
  forEachPiece(buffer, t0, t1,
               [&](const Eigen::Vector3d& gyr, const Eigen::Vector3d& acc, double dt) {
                 // The piece's attitude at its middle carries its specific force into the world.
                 const Eigen::Quaterniond q_mid = q * expQuat((gyr - start.bias_gyr) * (0.5 * dt));
                 const Eigen::Vector3d a_world = q_mid * (acc - start.bias_acc) + g_world;
                 p += v * dt + 0.5 * a_world * dt * dt;
                 v += a_world * dt;
                 q = q * expQuat((gyr - start.bias_gyr) * dt);
               });
  const Eigen::Quaterniond q0 = start.q_world_body.normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (q0.conjugate() * q.normalized()).toRotationMatrix();
  T.translation() = q0.conjugate() * p;
  if (end) {
    *end = start;
    end->q_world_body = q.normalized();
    end->v_world = v;
  }
  return T;
}

Eigen::Vector3d gyroRate(const ImuBuffer& buffer, double t, const Eigen::Vector3d& bias_gyr) {
  if (buffer.empty()) return Eigen::Vector3d::Zero();
  if (t <= buffer.oldestTime()) return buffer.samples().front().gyr - bias_gyr;
  if (t >= buffer.newestTime()) return buffer.samples().back().gyr - bias_gyr;
  return buffer.interpolate(t).gyr - bias_gyr;
}

}  // namespace rgbdi::imu
