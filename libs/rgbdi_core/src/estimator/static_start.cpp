#include "estimator/static_start.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "rgbdi/imu/imu_buffer.h"

namespace rgbdi::estimator {

namespace {

Stillness notStill(const char* why) {
  Stillness s;
  s.failure = why;
  return s;
}

}  // namespace

StaticStart::StaticStart(const EstimatorOptions& opt, const ImuOptions& imu)
    : opt_(opt), gravity_m_s2_(imu.gravity_m_s2) {}

void StaticStart::addFrame(double t, const std::vector<frontend::FeatureObservation>& features) {
  frames_.push_back({t, features});
  while (frames_.size() > 2 && frames_.front().t < t - 2.0 * opt_.init_static_window_s)
    frames_.pop_front();
}

Stillness StaticStart::judge(const frontend::FeatureFrame& frame, double t,
                             const imu::ImuBuffer& imu) const {
  // The frame the features are compared with: the oldest recent one inside the stillness window
  // that is at least half the window old. Images further apart than that (a slow camera, a live
  // run dropping images) have none: then the previous frame, and stillness is judged over the
  // whole time since it (more data: the same thresholds are only stricter).
  const Frame* oldest = nullptr;
  double t_start = t - opt_.init_static_window_s;
  for (const auto& s : frames_)
    if (s.t >= t_start - 1e-9) {
      oldest = &s;
      break;
    }
  if ((!oldest || t - oldest->t < 0.5 * opt_.init_static_window_s) && frames_.size() >= 2) {
    const Frame& prev = frames_[frames_.size() - 2];
    if (prev.t < t_start) {
      oldest = &prev;
      t_start = prev.t;
    }
  }
  if (imu.empty() || imu.oldestTime() > t_start || imu.newestTime() < t)
    return notStill("not enough IMU history for the stillness test");
  // IMU: mean gyro small, |mean acc| close to g, and little spread of 50 ms means.
  Eigen::Vector3d sum_acc = Eigen::Vector3d::Zero(), sum_gyr = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> bins;
  Eigen::Vector3d bin_sum = Eigen::Vector3d::Zero();
  int bin_n = 0, n = 0;
  double bin_start = t_start;
  constexpr double kBin = 0.05;  // averaging interval for the spread test [s]
  for (const ImuSample& m : imu.samples()) {
    if (m.t < t_start || m.t > t) continue;
    sum_acc += m.acc;
    sum_gyr += m.gyr;
    ++n;
    if (m.t - bin_start > kBin && bin_n > 0) {
      bins.push_back(bin_sum / bin_n);
      bin_sum.setZero();
      bin_n = 0;
      bin_start = m.t;
    }
    bin_sum += m.acc;
    ++bin_n;
  }
  if (n < 10 || bins.size() < 3) return notStill("too few IMU samples in the stillness window");
  Stillness still;
  still.mean_acc = sum_acc / n;
  still.mean_gyr = sum_gyr / n;
  if (still.mean_gyr.norm() > opt_.init_static_max_gyro_rad_s)
    return notStill("gyro mean above init_static_max_gyro_rad_s");
  if (std::abs(still.mean_acc.norm() - gravity_m_s2_) > opt_.init_static_max_acc_dev_m_s2)
    return notStill("|mean acc| differs from g by more than init_static_max_acc_dev_m_s2");
  double var = 0.0;
  for (const auto& b : bins) var += (b - still.mean_acc).squaredNorm();
  if (std::sqrt(var / static_cast<double>(bins.size())) > opt_.init_static_max_acc_std_m_s2)
    return notStill("accelerometer spread above init_static_max_acc_std_m_s2");
  // Vision: the features of that frame must not have moved.
  if (!oldest || t - oldest->t < 0.5 * opt_.init_static_window_s)
    return notStill("not enough frames in the stillness window");
  std::unordered_map<std::uint64_t, Eigen::Vector2d> old_pos;
  for (const auto& f : oldest->features) old_pos[f.id] = f.xn;
  double motion = 0.0;
  int matched = 0;
  for (const auto& f : frame.features) {
    const auto it = old_pos.find(f.id);
    if (it == old_pos.end()) continue;
    motion += (f.xn - it->second).norm();
    ++matched;
  }
  if (matched < opt_.keyframe_min_tracked ||
      motion / matched > opt_.init_static_max_motion_px / EstimatorOptions::kVirtualFocalPx)
    return notStill("features moved (or too few tracked) during the stillness window");
  return still;
}

}  // namespace rgbdi::estimator
