#include "estimator/depth_aided_start.h"

#include <algorithm>
#include <cstdint>
#include <exception>
#include <unordered_map>
#include <vector>

#include "estimator/frame_window.h"
#include "rgbdi/estimator/initializer.h"
#include "rgbdi/imu/imu_init.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

namespace {

/// [px at the virtual focal] mean feature motion between the oldest and the newest slot.
double parallaxOverWindow(const FrameWindow& window) {
  std::unordered_map<std::uint64_t, Eigen::Vector2d> first;
  for (const auto& f : window.front().raw_features) first[f.id] = f.xn;
  double sum = 0.0;
  int cnt = 0;
  for (const auto& f : window.back().raw_features) {
    const auto it = first.find(f.id);
    if (it == first.end()) continue;
    sum += (f.xn - it->second).norm();
    ++cnt;
  }
  return cnt > 0 ? sum / cnt * EstimatorOptions::kVirtualFocalPx : 0.0;
}

}  // namespace

bool newestSlotHasDepthForPnp(const FrameWindow& window, const EstimatorOptions& opt) {
  int with_depth = 0;
  for (const auto& f : window.back().raw_features)
    if (f.depth_m > 0.0 && f.depth_m <= opt.init_depth_max_m) ++with_depth;
  return with_depth >= opt.init_min_correspondences;
}

MovingStart solveDepthAidedStart(FrameWindow& window, double td, const EstimatorOptions& opt,
                                 const ImuOptions& imu, const Eigen::Isometry3d& T_body_cam,
                                 mrpt::system::COutputLogger& log) {
  // PnP of the newest frame against the previous one (metric points from the previous depth).
  const size_t n = window.size();
  if (n >= 2) {
    const WindowSlot& prev = window[n - 2];
    WindowSlot& cur = window[n - 1];
    std::unordered_map<std::uint64_t, const frontend::FeatureObservation*> prev_by_id;
    for (const auto& f : prev.raw_features)
      if (f.depth_m > 0.0 && f.depth_m <= opt.init_depth_max_m) prev_by_id[f.id] = &f;
    std::vector<Eigen::Vector3d> pts;
    std::vector<Eigen::Vector2d> xn;
    for (const auto& f : cur.raw_features) {
      const auto it = prev_by_id.find(f.id);
      if (it == prev_by_id.end()) continue;
      pts.push_back(Eigen::Vector3d(it->second->xn.x(), it->second->xn.y(), 1.0) *
                    it->second->depth_m);
      xn.push_back(f.xn);
    }
    PnpOptions popt;
    popt.min_inliers = opt.init_min_correspondences;
    popt.seed = cur.frame_index + 1;
    const auto pnp = relativePoseByPnP(pts, xn, popt);
    if (!pnp) {
      // The chain is broken: start the initialisation window again from this frame.
      window.restartFromNewest(td);
      log.logFmt(mrpt::system::LVL_DEBUG, "PnP with %zu depth-backed correspondences failed\n",
                 pts.size());
      return MovingStart::failed("PnP between consecutive frames failed");
    }
    cur.T_c0_c = prev.T_c0_c * pnp->T_curr_prev.inverse();
  }
  if (static_cast<int>(window.size()) < opt.init_min_frames ||
      window.back().t - window.front().t < opt.init_min_span_s) {
    return MovingStart::failed("too few frames or too short a span for a moving initialisation");
  }
  // Enough parallax, or a full window (depth makes the problem metric, so excitation is not
  // needed: waiting longer only delays the first pose).
  if (parallaxOverWindow(window) < opt.init_min_parallax_px &&
      static_cast<int>(window.size()) < opt.window_size) {
    return MovingStart::failed("not enough parallax yet");
  }

  // Body poses in the first camera's frame.
  MovingStart start;
  std::vector<const imu::Preintegration*> pre;
  const Eigen::Isometry3d T_cb = T_body_cam.inverse();
  for (const auto& s : window) {
    start.T_ref_body.push_back(s.T_c0_c * T_cb);
    pre.push_back(s.preint.get());
  }
  // Gyro bias from the visual rotations.
  std::vector<imu::GyroBiasPair> pairs;
  for (size_t k = 1; k < window.size(); ++k) {
    const Eigen::Quaterniond q_rel(start.T_ref_body[k - 1].rotation().transpose() *
                                   start.T_ref_body[k].rotation());
    pairs.emplace_back(q_rel, pre[k]);
  }
  start.bg = window.front().bg();
  try {
    start.bg += imu::solveGyroBias(pairs);
  } catch (const std::exception&) {
    return MovingStart::failed("gyro-bias solve failed");
  }
  if (start.bg.norm() > opt.fail_max_gyr_bias_rad_s)
    return MovingStart::failed("gyro bias above fail_max_gyr_bias_rad_s");
  for (size_t k = 1; k < window.size(); ++k)
    window[k].preint->repropagate(Eigen::Vector3d::Zero(), start.bg);
  const auto align = alignVelocitiesAndGravity(start.T_ref_body, pre, imu.gravity_m_s2);
  if (!align) return MovingStart::failed("velocity/gravity alignment failed or inconsistent");
  // IMU data that disagree with the visual motion (a shock, or the tail of the failure that
  // caused this re-initialisation) leave a large residual: wait for clean data instead.
  const double mean_interval_s =
      (window.back().t - window.front().t) / static_cast<double>(window.size() - 1);
  const double gate =
      opt.init_max_alignment_rms * std::max(1.0, mean_interval_s / opt.init_alignment_interval_s);
  if (align->residual_rms > gate)
    return MovingStart::failed(
        "IMU and visual motion disagree (alignment residual above init_max_alignment_rms, scaled "
        "by the mean image interval over init_alignment_interval_s)");
  start.v_ref = align->v_ref;
  start.g_ref = align->g_ref;
  return start;
}

}  // namespace rgbdi::estimator
