#include "rgbdi/imu/gyro_rotation.h"

#include <algorithm>

#include "rgbdi/common/so3.h"

namespace rgbdi::imu {

Eigen::Quaterniond gyroRotation(const ImuBuffer& buffer, double t0, double t1,
                                const Eigen::Vector3d& bias_gyr) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (buffer.empty() || !(t1 > t0)) return q;
  const double oldest = buffer.oldestTime(), newest = buffer.newestTime();
  auto hold = [&](const Eigen::Vector3d& rate, double from, double to) {
    if (to > from) q = q * expQuat((rate - bias_gyr) * (to - from));
  };
  // Before the buffered span: the oldest sample's rate.
  hold(buffer.samples().front().gyr, t0, std::min(t1, oldest));
  const double a = std::max(t0, oldest), b = std::min(t1, newest);
  if (b > a) {
    const std::vector<ImuSample> s = buffer.between(a, b);
    for (std::size_t k = 0; k + 1 < s.size(); ++k)
      q = q * expQuat((0.5 * (s[k].gyr + s[k + 1].gyr) - bias_gyr) * (s[k + 1].t - s[k].t));
  }
  // After it: the newest sample's rate.
  hold(buffer.samples().back().gyr, std::max(t0, newest), t1);
  return q.normalized();
}

}  // namespace rgbdi::imu
