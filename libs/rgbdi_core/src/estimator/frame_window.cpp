#include "estimator/frame_window.h"

#include <algorithm>
#include <utility>

#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/imu/imu_buffer.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

FrameWindow::FrameWindow(const EstimatorOptions& opt, const ImuOptions& imu)
    : opt_(opt), imu_opt_(imu) {
  slots_.reserve(static_cast<size_t>(opt.window_size) + 2);
}

std::vector<std::pair<std::uint64_t, TrackObservation>> FrameWindow::toObservations(
    const std::vector<frontend::FeatureObservation>& features, double td,
    bool at_reference_time) const {
  std::vector<std::pair<std::uint64_t, TrackObservation>> out;
  out.reserve(features.size());
  for (const auto& f : features) {
    TrackObservation o;
    o.meas.xn = Eigen::Vector3d(f.xn.x(), f.xn.y(), 1.0);
    o.meas.velocity = f.velocity_xn;
    o.meas.td_at_stamp = td;
    o.uv = f.uv;
    o.depth_m = f.depth_m;
    o.xn_row = f.xn;
    o.row_time_s = rolling_shutter_.rowTime(f.uv.y());
    o.meas.row_fraction = rolling_shutter_.rowFraction(f.uv.y());
    o.meas.readout_at_stamp_s = rolling_shutter_.readout_s;
    if (at_reference_time)
      o.xn_row += o.row_time_s * f.velocity_xn;
    else
      o.compensateRollingShutter();
    out.emplace_back(f.id, o);
  }
  return out;
}

double FrameWindow::add(const frontend::FeatureFrame& frame, double t, double td,
                        const imu::ImuBuffer& imu, bool predict_from_previous, bool bridged,
                        const Eigen::Isometry3d& T_body_cam) {
  const double t0 = threadCpuSeconds();
  double preintegration_ms = 0.0;
  WindowSlot s;
  s.t = t;
  s.t_image = frame.t;
  s.frame_index = frame.frame_index;
  s.raw_features = frame.features;
  moveToReferenceTime(s.raw_features, rolling_shutter_);
  if (!slots_.empty()) {
    const WindowSlot& prev = slots_.back();
    s.preint = std::make_unique<imu::Preintegration>(prev.ba(), prev.bg(),
                                                     imu::ImuNoise::fromOptions(imu_opt_));
    for (const ImuSample& m : imu.between(prev.t, t)) s.preint->push(m);
    preintegration_ms = 1e3 * (threadCpuSeconds() - t0);
    std::copy(prev.sb, prev.sb + 9, s.sb);
    std::copy(prev.pose, prev.pose + 7, s.pose);
    if (predict_from_previous) {
      Eigen::Vector3d Pj, Vj;
      Eigen::Quaterniond Qj;
      s.preint->predict(prev.p(), prev.q(), prev.v(), Eigen::Vector3d(0, 0, -imu_opt_.gravity_m_s2),
                        Pj, Qj, Vj);
      s.setPose(Pj, Qj);
      s.setV(Vj);
    }
    if (bridged) s.bridged_s = t - prev.t;
  }
  slots_.push_back(std::move(s));
  // The keyframe parallax is measured between the two slots before the new one.
  Eigen::Matrix3d R_c2_c1;
  const bool without_rotation = opt_.keyframe_parallax_without_rotation && slots_.size() >= 3;
  if (without_rotation) {
    const Eigen::Matrix3d R_bc = T_body_cam.rotation();
    const Eigen::Quaterniond q2 = slots_[slots_.size() - 3].q(), q1 = slots_[slots_.size() - 2].q();
    R_c2_c1 = R_bc.transpose() * (q2.conjugate() * q1).toRotationMatrix() * R_bc;
  }
  const FeatureManager::FrameLinks links = features_.addFrame(
      static_cast<int>(slots_.size()) - 1, toObservations(frame.features, td, false),
      without_rotation ? &R_c2_c1 : nullptr);
  const double min_parallax = opt_.keyframe_parallax_px / EstimatorOptions::kVirtualFocalPx;
  // A second-newest frame that shares no feature with the frame before it shows a new view (the
  // first frame after blind ones): a keyframe, or the window would never take the new features
  // in (they would only ever be seen in its two newest slots, one of them always dropped).
  newest_but_one_keyframe_ = slots_.size() < 3 || links.n_tracked < opt_.keyframe_min_tracked ||
                             links.n_parallax == 0 || links.parallax >= min_parallax;
  return preintegration_ms;
}

void FrameWindow::dropSecondNewest() {
  const size_t N = slots_.size() - 1;
  WindowSlot& s1 = slots_[N - 1];
  // Merge pre-integrations: (N-2 -> N-1) followed by (N-1 -> N).
  auto merged = std::make_unique<imu::Preintegration>(s1.preint->biasAcc(), s1.preint->biasGyr(),
                                                      imu::ImuNoise::fromOptions(imu_opt_));
  for (const auto& m : s1.preint->samples()) merged->push(m);
  const auto& next = slots_[N].preint->samples();
  for (size_t k = 1; k < next.size(); ++k) merged->push(next[k]);
  slots_[N].preint = std::move(merged);
  slots_[N].bridged_s += s1.bridged_s;
  features_.removeSlot(static_cast<int>(N) - 1);
  slots_.erase(slots_.begin() + static_cast<std::ptrdiff_t>(N) - 1);
}

void FrameWindow::removeOldest(const Eigen::Isometry3d& T_body_cam) {
  features_.removeOldest(poses(), T_body_cam);
  slots_.erase(slots_.begin());
  slots_.front().preint.reset();
}

void FrameWindow::restartFromNewest(double td) {
  WindowSlot keep = std::move(slots_.back());
  slots_.clear();
  features_.clear();
  keep.preint.reset();
  keep.T_c0_c = Eigen::Isometry3d::Identity();
  slots_.push_back(std::move(keep));
  features_.addFrame(0, toObservations(slots_.front().raw_features, td, true));
}

void FrameWindow::clear() {
  slots_.clear();
  features_.clear();
}

void FrameWindow::rejectOutliers(double threshold_norm, const Eigen::Isometry3d& T_body_cam) {
  const int newest = static_cast<int>(slots_.size()) - 1;
  for (auto& [id, f] : features_.tracks()) {
    if (!FeatureManager::usable(f, newest)) continue;
    const Eigen::Isometry3d T_w_ci = slots_[static_cast<size_t>(f.start_slot)].T() * T_body_cam;
    const Eigen::Vector3d p_w = T_w_ci * (f.obs.front().meas.xn / f.inv_depth);
    double err = 0.0;
    for (size_t k = 1; k < f.obs.size(); ++k) {
      const Eigen::Isometry3d T_w_cj =
          slots_[static_cast<size_t>(f.start_slot) + k].T() * T_body_cam;
      const Eigen::Vector3d p_c = T_w_cj.inverse() * p_w;
      err += p_c.z() > 0 ? (p_c.head<2>() / p_c.z() - f.obs[k].meas.xn.head<2>()).norm() : 1.0;
    }
    if (err / static_cast<double>(f.obs.size() - 1) > threshold_norm) f.outlier = true;
  }
  features_.removeOutliers();
}

SlotPoses FrameWindow::poses() const {
  SlotPoses poses;
  poses.reserve(slots_.size());
  for (const auto& s : slots_) poses.push_back(s.T());
  return poses;
}

std::vector<KeyframeState> FrameWindow::keyframeStates(int segment,
                                                       const imu::ImuBuffer* imu) const {
  std::vector<KeyframeState> out;
  for (const auto& s : slots_) {
    out.push_back({s.t, s.T(), s.frame_index, segment, s.bridged_s});
    out.back().v_world = s.v();
    if (imu && imu->covers(s.t, s.t)) out.back().omega_body = imu->interpolate(s.t).gyr - s.bg();
    out.back().rolling_shutter_readout_s = rolling_shutter_.readout_s;
  }
  return out;
}

}  // namespace rgbdi::estimator
