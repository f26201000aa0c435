#include "rgbdi/estimator/sliding_window_estimator.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_map>

#include "estimator/static_start.h"
#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/estimator/gauge_prior.h"
#include "rgbdi/estimator/initializer.h"
#include "rgbdi/estimator/marginalization.h"
#include "rgbdi/estimator/motion_field.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/scalar_prior.h"
#include "rgbdi/estimator/scale_alignment.h"
#include "rgbdi/estimator/speed_bias_prior.h"
#include "rgbdi/estimator/visual_sfm.h"
#include "rgbdi/estimator/window_solver.h"
#include "rgbdi/imu/imu_buffer.h"
#include "rgbdi/imu/imu_factor.h"
#include "rgbdi/imu/imu_init.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

const char* toString(EstimatorStatus s) {
  switch (s) {
    case EstimatorStatus::kInitializing:
      return "initialising";
    case EstimatorStatus::kTracking:
      return "tracking";
    case EstimatorStatus::kLost:
      return "lost";
  }
  return "?";
}

namespace {

// Sqrt information of the gauge prior [1/m, 1/rad]: stiff enough to act as a constraint, soft
// enough to keep the normal equations well conditioned.
constexpr double kGaugeStiffness = 1e4;
// [1/m] lower bound of a solved inverse depth (1 km): a feature beyond it carries no depth
// information, and the bound keeps a step from flipping it behind the camera.
constexpr double kMinInverseDepth = 1e-3;

/// Stage timings are thread CPU time: on a shared machine wall time mostly measures the others.
double msSince(double cpu_t0_s) { return 1e3 * (threadCpuSeconds() - cpu_t0_s); }

}  // namespace

double SlidingWindowEstimator::depthPriorSigma(const FeatureTrack& f) const {
  // Depth sigma = c z^2 means inverse-depth sigma = c, averaged over independent observations.
  return opt_.depth_noise_coeff / std::sqrt(std::max(1, f.verified_observations));
}

/// One frame in the window: its optimisation variables and the IMU interval leading to it.
struct SlidingWindowEstimator::Slot {
  double t = 0.0;        ///< IMU-clock time
  double t_image = 0.0;  ///< image stamp
  std::uint64_t frame_index = 0;
  double pose[7] = {0, 0, 0, 0, 0, 0, 1};
  double sb[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  std::unique_ptr<imu::Preintegration> preint;  ///< previous slot -> this slot (null for slot 0)
  /// [s] of the interval from the previous slot carried by the IMU alone (blind frames in it)
  double bridged_s = 0.0;
  /// Camera pose of this frame relative to the first frame of a moving initialisation (PnP).
  Eigen::Isometry3d T_c0_c = Eigen::Isometry3d::Identity();
  std::vector<frontend::FeatureObservation> raw_features;  ///< for PnP during initialisation

  Eigen::Vector3d p() const { return Eigen::Vector3d(pose[0], pose[1], pose[2]); }
  Eigen::Quaterniond q() const { return Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]); }
  Eigen::Vector3d v() const { return Eigen::Vector3d(sb[0], sb[1], sb[2]); }
  Eigen::Vector3d ba() const { return Eigen::Vector3d(sb[3], sb[4], sb[5]); }
  Eigen::Vector3d bg() const { return Eigen::Vector3d(sb[6], sb[7], sb[8]); }
  Eigen::Isometry3d T() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q().normalized().toRotationMatrix();
    T.translation() = p();
    return T;
  }
  void setPose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    const Eigen::Quaterniond qn = q.normalized();
    pose[0] = p.x();
    pose[1] = p.y();
    pose[2] = p.z();
    pose[3] = qn.x();
    pose[4] = qn.y();
    pose[5] = qn.z();
    pose[6] = qn.w();
  }
  void setV(const Eigen::Vector3d& v) {
    sb[0] = v.x();
    sb[1] = v.y();
    sb[2] = v.z();
  }
  void setBiases(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) {
    for (int i = 0; i < 3; ++i) {
      sb[3 + i] = ba[i];
      sb[6 + i] = bg[i];
    }
  }
};

void SlidingWindowEstimator::assignMotionFieldVelocities(std::size_t slot) {
  if (opt_.time_offset_velocity != "motion_field") return;
  const Slot& s = window_[slot];
  if (!imu_->covers(s.t, s.t)) return;
  const Eigen::Vector3d w_b = imu_->interpolate(s.t).gyr - s.bg();
  const Eigen::Matrix3d R_cb = T_bc_.rotation().transpose();
  const Eigen::Vector3d w_c = R_cb * w_b;
  // Velocity of the camera centre, in the camera frame (the lever arm adds omega x t_bc).
  const Eigen::Vector3d v_c =
      R_cb * (s.q().normalized().conjugate() * s.v() + w_b.cross(T_bc_.translation()));
  const Eigen::Isometry3d T_c_w = (s.T() * T_bc_).inverse();
  const int slot_i = static_cast<int>(slot);
  // Depth of each observation: measured, else from the track's estimate; features with neither
  // get the median of the others (the translational term only needs a rough depth).
  std::vector<std::pair<TrackObservation*, double>> todo;
  std::vector<double> known;
  for (auto& [id, f] : features_.tracks()) {
    if (f.start_slot > slot_i || f.endSlot() < slot_i) continue;
    TrackObservation& o = f.obs[static_cast<std::size_t>(slot_i - f.start_slot)];
    double z = o.depth_m;
    if (!(z > 0.0) && f.hasDepth()) {
      const Eigen::Isometry3d T_w_ci = window_[static_cast<std::size_t>(f.start_slot)].T() * T_bc_;
      z = (T_c_w * (T_w_ci * (f.obs.front().meas.xn / f.inv_depth))).z();
    }
    if (z > 0.0) known.push_back(z);
    todo.emplace_back(&o, z);
  }
  double typical = 0.0;
  if (!known.empty()) {
    std::nth_element(known.begin(), known.begin() + known.size() / 2, known.end());
    typical = known[known.size() / 2];
  }
  for (auto& [o, z] : todo)
    o->meas.velocity = motionFieldVelocity(o->meas.xn.head<2>(), z > 0.0 ? z : typical, w_c, v_c);
}

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& opt, const ImuOptions& imu,
                                               const ExtrinsicOptions& ext)
    : mrpt::system::COutputLogger("rgbdi.estimator"),
      opt_(opt),
      imu_opt_(imu),
      T_bc_(ext.T_body_cam),
      td_(ext.time_offset_s),
      td_config_(ext.time_offset_s),
      sqrt_info_(EstimatorOptions::kVirtualFocalPx / opt.reprojection_sigma_px),
      imu_(std::make_unique<imu::ImuBuffer>()),
      static_start_(std::make_unique<StaticStart>(opt, imu)) {
  depth_opt_.tolerance_norm = opt.depth_verify_tolerance_px / EstimatorOptions::kVirtualFocalPx;
  depth_opt_.min_depth_m = opt.depth_verify_min_m;
  depth_opt_.max_depth_m = opt.depth_verify_max_m;
  depth_opt_.hold_constant = opt.verified_depth == "constant";
  td_param_[0] = td_;
  window_.reserve(static_cast<size_t>(opt.window_size) + 2);
}

SlidingWindowEstimator::~SlidingWindowEstimator() = default;

bool SlidingWindowEstimator::initFail(const char* why) {
  init_fail_reason_ = why;
  logFmt(mrpt::system::LVL_DEBUG, "initialisation not yet possible: %s\n", why);
  return false;
}

void SlidingWindowEstimator::feedImu(const ImuSample& s) {
  if (!imu_->empty() && s.t <= imu_->newestTime())
    return;  // the stream stage already reports these
  imu_->push(s);
}

Eigen::Vector3d SlidingWindowEstimator::gyroBias() const {
  return window_.empty() ? Eigen::Vector3d::Zero() : window_.back().bg();
}

double SlidingWindowEstimator::latestImuTime() const {
  return imu_->empty() ? -1e300 : imu_->newestTime();
}

std::vector<std::pair<std::uint64_t, TrackObservation>> SlidingWindowEstimator::toObservations(
    const frontend::FeatureFrame& frame) const {
  std::vector<std::pair<std::uint64_t, TrackObservation>> out;
  out.reserve(frame.features.size());
  for (const auto& f : frame.features) {
    TrackObservation o;
    o.meas.xn = Eigen::Vector3d(f.xn.x(), f.xn.y(), 1.0);
    o.meas.velocity = f.velocity_xn;
    o.meas.td_at_stamp = td_;
    o.uv = f.uv;
    o.depth_m = f.depth_m;
    out.emplace_back(f.id, o);
  }
  return out;
}

SlotPoses SlidingWindowEstimator::slotPoses() const {
  SlotPoses poses;
  poses.reserve(window_.size());
  for (const auto& s : window_) poses.push_back(s.T());
  return poses;
}

void SlidingWindowEstimator::addSlot(const frontend::FeatureFrame& frame, double t,
                                     bool predict_from_previous) {
  const double t0 = threadCpuSeconds();
  last_preintegration_ms_ = 0.0;
  Slot s;
  s.t = t;
  s.t_image = frame.t;
  s.frame_index = frame.frame_index;
  s.raw_features = frame.features;
  if (!window_.empty()) {
    const Slot& prev = window_.back();
    s.preint = std::make_unique<imu::Preintegration>(prev.ba(), prev.bg(),
                                                     imu::ImuNoise::fromOptions(imu_opt_));
    for (const ImuSample& m : imu_->between(prev.t, t)) s.preint->push(m);
    last_preintegration_ms_ = msSince(t0);
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
    if (bridging_) s.bridged_s = t - prev.t;
  }
  bridging_ = false;
  window_.push_back(std::move(s));
  const FeatureManager::FrameLinks links =
      features_.addFrame(static_cast<int>(window_.size()) - 1, toObservations(frame));
  if (predict_from_previous) assignMotionFieldVelocities(window_.size() - 1);
  const double min_parallax = opt_.keyframe_parallax_px / EstimatorOptions::kVirtualFocalPx;
  // A second-newest frame that shares no feature with the frame before it shows a new view (the
  // first frame after blind ones): a keyframe, or the window would never take the new features
  // in (they would only ever be seen in its two newest slots, one of them always dropped).
  newest_but_one_keyframe_ = window_.size() < 3 || links.n_tracked < opt_.keyframe_min_tracked ||
                             links.n_parallax == 0 || links.parallax >= min_parallax;
  // Keep what the window needs, and enough history for the stillness test of initialisation:
  // while initialising, back to the oldest stillness frame (the test may judge stillness since
  // the previous frame, however long ago that was).
  double keep_from = std::min(window_.front().t, t - 2.0 * opt_.init_static_window_s);
  if (status_ != EstimatorStatus::kTracking && !static_start_->empty())
    keep_from = std::min(keep_from, static_start_->oldestFrameTime());
  imu_->popOlderThan(keep_from);
  stats_.sum_ms_preintegration += last_preintegration_ms_;
}

bool SlidingWindowEstimator::tryStaticInit(const frontend::FeatureFrame& frame, double t) {
  const Stillness still = static_start_->judge(frame, t, *imu_);
  if (still.failure) return initFail(still.failure);
  const Eigen::Vector3d& mean_acc = still.mean_acc;
  const Eigen::Vector3d& mean_gyr = still.mean_gyr;

  // Still: attitude from gravity, zero velocity, gyro bias from the mean rate.
  const double yaw = have_anchor_ ? anchor_yaw_ : 0.0;
  const Eigen::Matrix3d R = attitudeFromGravity(mean_acc, yaw);
  window_.clear();
  features_.clear();
  prior_.reset();
  addSlot(frame, t, false);
  Slot& s = window_.front();
  s.setPose(have_anchor_ ? anchor_p_ : Eigen::Vector3d::Zero(), Eigen::Quaterniond(R));
  s.setV(Eigen::Vector3d::Zero());
  s.setBiases(Eigen::Vector3d::Zero(), mean_gyr);
  init_prior_mean_.setZero();
  init_prior_mean_.tail<3>() = mean_gyr;
  init_prior_sigma_ << Eigen::Vector3d::Constant(opt_.init_static_velocity_sigma_m_s),
      Eigen::Vector3d::Constant(opt_.init_acc_bias_sigma_m_s2),
      Eigen::Vector3d::Constant(opt_.init_gyr_bias_sigma_rad_s);
  use_init_prior_ = true;
  ++stats_.static_initialisations;
  return true;
}

bool SlidingWindowEstimator::tryMovingInit() {
  // Frames without (enough) depth, e.g. --no-depth: the visual SfM initialisation.
  int with_depth = 0;
  for (const auto& f : window_.back().raw_features)
    if (f.depth_m > 0.0 && f.depth_m <= opt_.init_depth_max_m) ++with_depth;
  visual_init_mode_ = with_depth < opt_.init_min_correspondences;
  if (visual_init_mode_) return tryVisualInit();
  // PnP of the newest frame against the previous one (metric points from the previous depth).
  const size_t n = window_.size();
  if (n >= 2) {
    const Slot& prev = window_[n - 2];
    Slot& cur = window_[n - 1];
    std::unordered_map<std::uint64_t, const frontend::FeatureObservation*> prev_by_id;
    for (const auto& f : prev.raw_features)
      if (f.depth_m > 0.0 && f.depth_m <= opt_.init_depth_max_m) prev_by_id[f.id] = &f;
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
    popt.min_inliers = opt_.init_min_correspondences;
    popt.seed = cur.frame_index + 1;
    const auto pnp = relativePoseByPnP(pts, xn, popt);
    if (!pnp) {
      // The chain is broken: start the initialisation window again from this frame.
      Slot keep = std::move(window_.back());
      window_.clear();
      features_.clear();
      keep.preint.reset();
      keep.T_c0_c = Eigen::Isometry3d::Identity();
      window_.push_back(std::move(keep));
      frontend::FeatureFrame ff;
      ff.features = window_.front().raw_features;
      features_.addFrame(0, toObservations(ff));
      logFmt(mrpt::system::LVL_DEBUG, "PnP with %zu depth-backed correspondences failed\n",
             pts.size());
      return initFail("PnP between consecutive frames failed");
    }
    cur.T_c0_c = prev.T_c0_c * pnp->T_curr_prev.inverse();
  }
  if (static_cast<int>(window_.size()) < opt_.init_min_frames ||
      window_.back().t - window_.front().t < opt_.init_min_span_s) {
    return initFail("too few frames or too short a span for a moving initialisation");
  }
  // Enough parallax, or a full window (depth makes the problem metric, so excitation is not
  // needed: waiting longer only delays the first pose).
  double max_parallax = 0.0;
  {
    std::unordered_map<std::uint64_t, Eigen::Vector2d> first;
    for (const auto& f : window_.front().raw_features) first[f.id] = f.xn;
    double sum = 0.0;
    int cnt = 0;
    for (const auto& f : window_.back().raw_features) {
      const auto it = first.find(f.id);
      if (it == first.end()) continue;
      sum += (f.xn - it->second).norm();
      ++cnt;
    }
    max_parallax = cnt > 0 ? sum / cnt * EstimatorOptions::kVirtualFocalPx : 0.0;
  }
  if (max_parallax < opt_.init_min_parallax_px &&
      static_cast<int>(window_.size()) < opt_.window_size) {
    return initFail("not enough parallax yet");
  }

  // Body poses in the first camera's frame.
  std::vector<Eigen::Isometry3d> T_ref_body;
  std::vector<const imu::Preintegration*> pre;
  const Eigen::Isometry3d T_cb = T_bc_.inverse();
  for (const auto& s : window_) {
    T_ref_body.push_back(s.T_c0_c * T_cb);
    pre.push_back(s.preint.get());
  }
  // Gyro bias from the visual rotations.
  std::vector<imu::GyroBiasPair> pairs;
  for (size_t k = 1; k < window_.size(); ++k) {
    const Eigen::Quaterniond q_rel(T_ref_body[k - 1].rotation().transpose() *
                                   T_ref_body[k].rotation());
    pairs.emplace_back(q_rel, pre[k]);
  }
  Eigen::Vector3d bg = window_.front().bg();
  try {
    bg += imu::solveGyroBias(pairs);
  } catch (const std::exception&) {
    return initFail("gyro-bias solve failed");
  }
  if (bg.norm() > opt_.fail_max_gyr_bias_rad_s)
    return initFail("gyro bias above fail_max_gyr_bias_rad_s");
  for (size_t k = 1; k < window_.size(); ++k)
    window_[k].preint->repropagate(Eigen::Vector3d::Zero(), bg);
  const auto align = alignVelocitiesAndGravity(T_ref_body, pre, imu_opt_.gravity_m_s2);
  if (!align) return initFail("velocity/gravity alignment failed or inconsistent");
  // IMU data that disagree with the visual motion (a shock, or the tail of the failure that
  // caused this re-initialisation) leave a large residual: wait for clean data instead.
  const double mean_interval_s =
      (window_.back().t - window_.front().t) / static_cast<double>(window_.size() - 1);
  const double gate =
      opt_.init_max_alignment_rms * std::max(1.0, mean_interval_s / opt_.init_alignment_interval_s);
  if (align->residual_rms > gate)
    return initFail(
        "IMU and visual motion disagree (alignment residual above init_max_alignment_rms, scaled "
        "by the mean image interval over init_alignment_interval_s)");

  adoptInitialisation(T_ref_body, align->v_ref, align->g_ref, bg);
  return true;
}

void SlidingWindowEstimator::adoptInitialisation(const std::vector<Eigen::Isometry3d>& T_ref_body,
                                                 const std::vector<Eigen::Vector3d>& v_ref,
                                                 const Eigen::Vector3d& g_ref,
                                                 const Eigen::Vector3d& bg) {
  // The reference frame becomes the world frame: gravity along -z, and position and yaw of the
  // oldest frame continue the trajectory from before a reset (or start at the origin).
  const double yaw0 = have_anchor_ ? anchor_yaw_ : 0.0;
  const Eigen::Matrix3d R_w_ref = worldFromGravity(g_ref, T_ref_body[0].rotation(), yaw0);
  const Eigen::Vector3d p0 = have_anchor_ ? anchor_p_ : Eigen::Vector3d::Zero();
  const Eigen::Vector3d shift = p0 - R_w_ref * T_ref_body[0].translation();
  for (size_t k = 0; k < window_.size(); ++k) {
    Slot& s = window_[k];
    s.setPose(R_w_ref * T_ref_body[k].translation() + shift,
              Eigen::Quaterniond(R_w_ref * T_ref_body[k].rotation()));
    s.setV(R_w_ref * v_ref[k]);
    s.setBiases(Eigen::Vector3d::Zero(), bg);
  }
  init_prior_mean_.setZero();
  init_prior_mean_.head<3>() = window_.front().v();
  init_prior_mean_.tail<3>() = bg;
  init_prior_sigma_ << Eigen::Vector3d::Constant(1.0),  // velocity: weak, the IMU factors decide
      Eigen::Vector3d::Constant(opt_.init_acc_bias_sigma_m_s2),
      Eigen::Vector3d::Constant(opt_.init_gyr_bias_sigma_rad_s);
  use_init_prior_ = true;
  ++stats_.moving_initialisations;
}

bool SlidingWindowEstimator::tryVisualInit() {
  // Without depth (VINS-Mono style): up-to-scale SfM over the window, then the IMU gives scale,
  // gravity, velocities and gyro bias. It needs a full window: the scale is observable only from
  // changes of acceleration, and a short window leaves it poorly determined.
  if (static_cast<int>(window_.size()) < opt_.window_size)
    return initFail("collecting frames for a visual (SfM) initialisation");
  std::vector<std::vector<frontend::FeatureObservation>> frames;
  std::vector<imu::Preintegration*> pre;
  for (auto& s : window_) {
    frames.push_back(s.raw_features);
    pre.push_back(s.preint.get());
  }
  SfmOptions so;
  so.min_correspondences = opt_.init_min_correspondences;
  so.min_parallax_norm = opt_.init_min_parallax_px / EstimatorOptions::kVirtualFocalPx;
  so.reprojection_sigma_norm = opt_.reprojection_sigma_px / EstimatorOptions::kVirtualFocalPx;
  so.seed = window_.back().frame_index + 1;
  const auto sfm = solveVisualSfm(frames, so);
  if (!sfm) return initFail("visual SfM over the window failed (parallax or tracks)");
  const auto align =
      alignWithScale(sfm->T_c0_c, T_bc_, pre, imu_opt_.gravity_m_s2, opt_.init_max_scale_rel_sigma);
  if (!align) return initFail("scale/gravity alignment failed or the scale is not observable yet");
  const Eigen::Vector3d bg = window_[1].preint->biasGyr();  // re-propagated with the solved bias
  if (bg.norm() > opt_.fail_max_gyr_bias_rad_s)
    return initFail("gyro bias above fail_max_gyr_bias_rad_s");
  std::vector<Eigen::Isometry3d> T_ref_body;
  const Eigen::Isometry3d T_cb = T_bc_.inverse();
  for (const auto& T : sfm->T_c0_c) {
    Eigen::Isometry3d T_metric = T;
    T_metric.translation() *= align->scale;
    T_ref_body.push_back(T_metric * T_cb);
  }
  logFmt(mrpt::system::LVL_INFO,
         "visual initialisation: scale %.4f (predicted rel. sigma %.3f), %d points\n", align->scale,
         align->scale_rel_sigma, sfm->n_points);
  adoptInitialisation(T_ref_body, align->v_ref, align->g_ref, bg);
  ++stats_.visual_initialisations;
  return true;
}

FrameEstimate SlidingWindowEstimator::processFrame(const frontend::FeatureFrame& frame) {
  FrameEstimate out;
  out.t_image = frame.t;
  const double t = frame.t + td_;
  out.t_imu = t;
  ++stats_.frames;
  if (!window_.empty() && t <= window_.back().t) return out;  // stale frame: ignore
  if (!imu_->covers(window_.empty() ? t : window_.back().t, t)) {
    // No IMU for this interval (start of stream or an IMU gap): restart initialisation.
    if (status_ == EstimatorStatus::kTracking) {
      logFmt(mrpt::system::LVL_WARN, "no IMU data up to t=%.3f: re-initialising\n", t);
      ++stats_.resets;
      reset(true);
      out.reset = true;
    } else {
      ++stats_.init_waits["no IMU data up to the image"];
    }
    out.status = status_;
    return out;
  }

  if (status_ != EstimatorStatus::kTracking) {
    static_start_->addFrame(t, frame.features);
    bool ok = opt_.init_allow_static && tryStaticInit(frame, t);
    if (!ok && opt_.init_allow_static)
      ++stats_.init_waits[std::string("static start: ") + init_fail_reason_];
    if (!ok) {
      addSlot(frame, t, false);
      ok = tryMovingInit();
      if (!ok) ++stats_.init_waits[std::string("moving start: ") + init_fail_reason_];
      if (!ok && visual_init_mode_ && window_.size() >= 3 && !newest_but_one_keyframe_) {
        // The SfM window holds keyframes (enough parallax between them), as the sliding window
        // does, so that it spans enough time for the scale to be observable.
        dropSecondNewestSlot();
      }
      if (!ok && static_cast<int>(window_.size()) > opt_.window_size) {
        // Keep the initialisation window bounded: forget the oldest frame.
        features_.removeOldest(slotPoses(), T_bc_);
        window_.erase(window_.begin());
        window_.front().preint.reset();
      }
    }
    if (!ok) {
      out.status = status_;
      return out;
    }
    status_ = EstimatorStatus::kTracking;
    last_sighted_t_ = frame.t;
    out.just_initialised = true;
    prior_.reset();
    features_.updateDepths(slotPoses(), T_bc_, depth_opt_);
    for (std::size_t k = 0; k < window_.size(); ++k) assignMotionFieldVelocities(k);
    if (window_.size() >= 2) optimise(&out, false);
  } else {
    out.blind = static_cast<int>(frame.features.size()) < opt_.fail_min_features;
    // Image stamps, not IMU-clock times: the time-offset estimate moves between the two frames
    // and would decide a blackout of exactly fail_max_blind_s (a whole number of frame periods)
    // by its last digits; the tolerance keeps round-off of the stamps out of it too.
    constexpr double kStampTolerance_s = 1e-3;
    if (!out.blind) {
      last_sighted_t_ = frame.t;
    } else if (opt_.fail_max_blind_s > 0.0 &&
               frame.t - last_sighted_t_ > opt_.fail_max_blind_s + kStampTolerance_s) {
      logFmt(mrpt::system::LVL_WARN,
             "t=%.3f: fewer than %d features for %.2f s: tracking lost, re-initialising\n", t,
             opt_.fail_min_features, frame.t - last_sighted_t_);
      ++stats_.resets;
      ++stats_.blind_resets;
      reset(true);
      out.reset = true;
      out.status = status_;
      return out;
    }
    // Blind frames get no slot: their pose is the IMU propagation of the newest sighted state,
    // and the window keeps the frames that saw something. The first frame that sees again joins
    // it through one pre-integration over the whole blind interval, so velocity and biases stay
    // held by the features seen before it (a window of featureless slots would leave them to
    // the IMU alone, and from there the estimate was seen to drift away after the images came
    // back), and the new frame's depth-verified features fix its position against them.
    const bool between_updates =
        opt_.update_rate_hz > 0.0 && t - window_.back().t < 0.9 / opt_.update_rate_hz;
    bridging_ = bridging_ || out.blind;
    if (out.blind || between_updates) {
      // Also between estimator updates (update_rate_hz): the IMU propagation of the newest slot.
      const double t0 = threadCpuSeconds();
      const Slot& s = window_.back();
      imu::Preintegration pre(s.ba(), s.bg(), imu::ImuNoise::fromOptions(imu_opt_));
      for (const ImuSample& m : imu_->between(s.t, t)) pre.push(m);
      Eigen::Vector3d P, V;
      Eigen::Quaterniond Q;
      pre.predict(s.p(), s.q(), s.v(), Eigen::Vector3d(0, 0, -imu_opt_.gravity_m_s2), P, Q, V);
      out.has_pose = true;
      out.T_world_body.linear() = Q.normalized().toRotationMatrix();
      out.T_world_body.translation() = P;
      out.v_world = V;
      out.bias_acc = s.ba();
      out.bias_gyr = s.bg();
      out.time_offset_s = td_;
      out.status = status_;
      out.ms_preintegration = msSince(t0);
      stats_.sum_ms_preintegration += out.ms_preintegration;
      return out;
    }
    addSlot(frame, t, true);
    out.ms_preintegration = last_preintegration_ms_;
    // The second-newest frame leaves the window after this update unless it is a keyframe.
    const bool leaving =
        !newest_but_one_keyframe_ && static_cast<int>(window_.size()) > opt_.window_size;
    optimise(&out, leaving && opt_.non_keyframe_update == "single_step");
    if (failureDetected()) {
      logFmt(mrpt::system::LVL_WARN, "failure detected at t=%.3f (%s): re-initialising\n", t,
             failureReason().c_str());
      ++stats_.resets;
      reset(true);
      out.reset = true;
      out.status = status_;
      return out;
    }
    rejectOutliers();
    // Depth verification and triangulation use the optimised poses (never the IMU-only
    // prediction of the newest frame): a verified depth is held constant afterwards, so any
    // pose error baked into it would persist.
    features_.updateDepths(slotPoses(), T_bc_, depth_opt_);
    if (static_cast<int>(window_.size()) > opt_.window_size) {
      marginaliseAndSlide(newest_but_one_keyframe_, &out);
    }
  }

  const Slot& s = window_.back();
  out.has_pose = true;
  out.T_world_body = s.T();
  out.v_world = s.v();
  out.bias_acc = s.ba();
  out.bias_gyr = s.bg();
  out.time_offset_s = td_;
  out.status = status_;
  out.t_imu = s.t;
  prev_newest_p_ = s.p();
  prev_newest_t_ = s.t;
  last_bg_ = s.bg();
  have_anchor_ = true;
  anchor_p_ = s.p();
  anchor_yaw_ = yawOf(s.T().rotation());
  last_good_window_ = windowKeyframes();
  if (stats_.first_pose_t_image < 0.0) stats_.first_pose_t_image = frame.t;
  return out;
}

void SlidingWindowEstimator::optimise(FrameEstimate* out, bool single_step) {
  const double t0 = threadCpuSeconds();
  const Eigen::Vector3d g_w(0, 0, -imu_opt_.gravity_m_s2);
  // The window's own solver (window_solver.h: the inverse depths eliminated, the frame blocks
  // solved densely); the factors live for this update only.
  WindowSolver& solver = solver_;
  solver.clear();
  std::vector<std::unique_ptr<ceres::CostFunction>> factors;
  auto addResidual = [&](const ceres::CostFunction* f, const ceres::LossFunction* loss,
                         std::initializer_list<double*> blocks) {
    residual_blocks_.assign(blocks);
    solver.addResidual(f, loss, residual_blocks_);
  };
  auto add = [&](ceres::CostFunction* f, const ceres::LossFunction* loss,
                 std::initializer_list<double*> blocks) {
    factors.emplace_back(f);
    addResidual(f, loss, blocks);
  };
  std::size_t reprojections = 0;
  auto reprojection = [&](const FeatureMeasurement& i, const FeatureMeasurement& j) {
    if (reprojections == reprojection_factors_.size())
      reprojection_factors_.push_back(
          std::make_unique<ReprojectionFactor>(i, j, T_bc_, sqrt_info_));
    else
      reprojection_factors_[reprojections]->reset(i, j, T_bc_, sqrt_info_);
    return reprojection_factors_[reprojections++].get();
  };
  const ceres::CauchyLoss cauchy(opt_.cauchy_loss_sigma);

  for (auto& s : window_) {
    solver.addFrameBlock(s.pose, 7);
    solver.addFrameBlock(s.sb, 9);
  }
  td_param_[0] = td_;
  if (opt_.estimate_time_offset) solver.addFrameBlock(td_param_, 1);
  if (prior_) solver.addPrior(prior_);
  // Gauge: hold position and yaw of the oldest pose (the prior carries no information on them).
  add(new GaugePrior(window_.front().pose, kGaugeStiffness), nullptr, {window_.front().pose});
  if (use_init_prior_) {
    add(new SpeedBiasPrior(init_prior_mean_, init_prior_sigma_), nullptr, {window_.front().sb});
    // The time offset is unobservable under uniform motion: anchor it to the configured value
    // until the marginalisation prior carries that information.
    if (opt_.estimate_time_offset)
      add(new ScalarPrior(td_config_, opt_.time_offset_prior_sigma_s), nullptr, {td_param_});
  }
  for (size_t k = 1; k < window_.size(); ++k) {
    Slot& a = window_[k - 1];
    Slot& b = window_[k];
    if (b.preint->needsRepropagation(a.ba(), a.bg(), opt_.repropagate_acc_bias_m_s2,
                                     opt_.repropagate_gyr_bias_rad_s)) {
      b.preint->repropagate(a.ba(), a.bg());
    }
    add(new imu::ImuFactor(b.preint.get(), g_w), nullptr, {a.pose, a.sb, b.pose, b.sb});
  }
  const int newest = static_cast<int>(window_.size()) - 1;
  int used = 0, verified = 0;
  // The inverse depths are solved in one buffer filled in track-id order (the solver's order
  // is the order of addition: the same bits whichever thread built the tracks).
  std::vector<FeatureTrack*> solved;
  for (auto& [id, f] : features_.tracks())
    if (FeatureManager::usable(f, newest)) solved.push_back(&f);
  inv_depth_params_.assign(solved.size(), 0.0);
  for (std::size_t n = 0; n < solved.size(); ++n) {
    FeatureTrack& f = *solved[n];
    double* inv_depth = &inv_depth_params_[n];
    *inv_depth = f.inv_depth;
    ++used;
    const bool held = f.depthVerified() && depth_opt_.hold_constant;
    if (!held) solver.addEliminatedScalar(inv_depth, kMinInverseDepth);
    const int i = f.start_slot;
    for (size_t k = 1; k < f.obs.size(); ++k) {
      const int j = i + static_cast<int>(k);
      addResidual(reprojection(f.obs.front().meas, f.obs[k].meas), &cauchy,
                  {window_[static_cast<size_t>(i)].pose, window_[static_cast<size_t>(j)].pose,
                   inv_depth, td_param_});
    }
    if (f.depthVerified()) {
      ++verified;
      if (!held)
        add(new ScalarPrior(f.verified_inv_depth, depthPriorSigma(f)), nullptr, {inv_depth});
    }
  }

  WindowSolverOptions so;
  // One step when the second-newest frame's measurements leave the window after this update
  // (the window is solved fully again with the next keyframe); not without depth-verified
  // features, where the scale rests on the IMU alone (as for the function tolerance below).
  single_step = single_step && verified > 0;
  so.max_iterations = single_step ? 1 : opt_.max_iterations;
  if (single_step) ++stats_.single_step_updates;
  so.function_tolerance =
      verified > 0 ? opt_.solver_function_tolerance : opt_.solver_function_tolerance_no_depth;
  so.max_time_s = opt_.max_solver_time_s;
  const WindowSolverSummary summary = solver.solve(so);
  for (std::size_t n = 0; n < solved.size(); ++n) solved[n]->inv_depth = inv_depth_params_[n];
  ++stats_.optimisations;
  stats_.solver_iterations += summary.successful_steps + summary.unsuccessful_steps;
  if (summary.termination == WindowSolverSummary::Termination::kNoConvergence)
    ++stats_.solver_iterations_capped;
  stats_.solver_factorisation_retries += summary.factorisation_retries;
  td_ = td_param_[0];
  for (auto& s : window_) s.setPose(s.p(), s.q());  // keep quaternions exactly unit

  out->n_features_used = used;
  out->n_depth_verified = verified;
  out->ms_optimisation = msSince(t0);
  stats_.sum_ms_optimisation += out->ms_optimisation;
}

void SlidingWindowEstimator::rejectOutliers() {
  const double thresh = opt_.outlier_reprojection_px / EstimatorOptions::kVirtualFocalPx;
  const int newest = static_cast<int>(window_.size()) - 1;
  for (auto& [id, f] : features_.tracks()) {
    if (!FeatureManager::usable(f, newest)) continue;
    const Eigen::Isometry3d T_w_ci = window_[static_cast<size_t>(f.start_slot)].T() * T_bc_;
    const Eigen::Vector3d p_w = T_w_ci * (f.obs.front().meas.xn / f.inv_depth);
    double err = 0.0;
    for (size_t k = 1; k < f.obs.size(); ++k) {
      const Eigen::Isometry3d T_w_cj = window_[static_cast<size_t>(f.start_slot) + k].T() * T_bc_;
      const Eigen::Vector3d p_c = T_w_cj.inverse() * p_w;
      err += p_c.z() > 0 ? (p_c.head<2>() / p_c.z() - f.obs[k].meas.xn.head<2>()).norm() : 1.0;
    }
    if (err / static_cast<double>(f.obs.size() - 1) > thresh) f.outlier = true;
  }
  features_.removeOutliers();
}

std::string SlidingWindowEstimator::failureReason() const {
  const Slot& s = window_.back();
  if (s.ba().norm() > opt_.fail_max_acc_bias_m_s2) return "accelerometer bias too large";
  if (s.bg().norm() > opt_.fail_max_gyr_bias_rad_s) return "gyro bias too large";
  const Eigen::Vector3d jump = s.p() - prev_newest_p_;
  if (jump.norm() > opt_.fail_max_jump_m) return "position jump";
  if (s.v().norm() > opt_.fail_max_speed_m_s) return "speed too high";
  const double dt = s.t - prev_newest_t_;
  if (dt > 0.0 && jump.norm() > opt_.fail_max_speed_m_s * dt)
    return "implausible motion between updates";
  if (std::abs(jump.z()) > opt_.fail_max_vertical_jump_m) return "vertical jump";
  for (const auto& w : window_)
    if (!w.p().allFinite() || !w.q().coeffs().allFinite()) return "non-finite state";
  return {};
}

bool SlidingWindowEstimator::failureDetected() const { return !failureReason().empty(); }

void SlidingWindowEstimator::reset(bool keep_anchor) {
  finished_keyframes_.insert(finished_keyframes_.end(), last_good_window_.begin(),
                             last_good_window_.end());
  last_good_window_.clear();
  if (status_ == EstimatorStatus::kTracking) ++segment_;
  if (!keep_anchor) have_anchor_ = false;
  window_.clear();
  features_.clear();
  prior_.reset();
  use_init_prior_ = false;
  static_start_->clear();
  bridging_ = false;
  status_ = EstimatorStatus::kInitializing;
}

void SlidingWindowEstimator::marginaliseAndSlide(bool newest_but_one_is_keyframe,
                                                 FrameEstimate* out) {
  const double t0 = threadCpuSeconds();
  const Eigen::Vector3d g_w(0, 0, -imu_opt_.gravity_m_s2);
  std::set<const double*> constant;
  if (!opt_.estimate_time_offset) constant.insert(td_param_);
  const size_t N = window_.size() - 1;  // index of the newest slot

  auto priorTouches = [&](const double* block) {
    if (!prior_) return false;
    for (const double* b : prior_->keptBlocks())
      if (b == block) return true;
    return false;
  };
  std::unordered_map<const double*, double*> remap;

  if (newest_but_one_is_keyframe) {
    // Marginalise the oldest keyframe with everything that observes it.
    auto info = std::make_shared<MarginalizationInfo>();
    Slot& s0 = window_[0];
    std::set<const double*> remove{s0.pose, s0.sb};
    if (prior_ && (priorTouches(s0.pose) || priorTouches(s0.sb))) {
      info->add({std::make_shared<MarginalizationFactor>(prior_), nullptr, prior_->keptBlocks()});
    }
    if (use_init_prior_) {
      info->add({std::make_shared<SpeedBiasPrior>(init_prior_mean_, init_prior_sigma_),
                 nullptr,
                 {s0.sb}});
      if (opt_.estimate_time_offset)
        info->add({std::make_shared<ScalarPrior>(td_config_, opt_.time_offset_prior_sigma_s),
                   nullptr,
                   {td_param_}});
      use_init_prior_ = false;  // from now on it lives inside the marginalisation prior
    }
    info->add({std::make_shared<imu::ImuFactor>(window_[1].preint.get(), g_w),
               nullptr,
               {s0.pose, s0.sb, window_[1].pose, window_[1].sb}});
    auto loss = std::make_shared<ceres::CauchyLoss>(opt_.cauchy_loss_sigma);
    const int newest = static_cast<int>(N);
    for (auto& [id, f] : features_.tracks()) {
      if (f.start_slot != 0 || !FeatureManager::usable(f, newest)) continue;
      for (size_t k = 1; k < f.obs.size(); ++k) {
        info->add({std::make_shared<ReprojectionFactor>(f.obs.front().meas, f.obs[k].meas, T_bc_,
                                                        sqrt_info_),
                   loss,
                   {s0.pose, window_[k].pose, &f.inv_depth, td_param_}});
      }
      // Depth-verified features held constant are not variables: nothing to marginalise.
      if (f.depthVerified() && depth_opt_.hold_constant) {
        constant.insert(&f.inv_depth);
      } else {
        remove.insert(&f.inv_depth);
        if (f.depthVerified()) {
          info->add({std::make_shared<ScalarPrior>(f.verified_inv_depth, depthPriorSigma(f)),
                     nullptr,
                     {&f.inv_depth}});
        }
      }
    }
    const bool kept = info->marginalize(remove, constant);
    finished_keyframes_.push_back({s0.t, s0.T(), s0.frame_index, segment_, s0.bridged_s});
    features_.removeOldest(slotPoses(), T_bc_);
    for (size_t k = 1; k <= N; ++k) {
      remap[window_[k].pose] = window_[k - 1].pose;
      remap[window_[k].sb] = window_[k - 1].sb;
    }
    window_.erase(window_.begin());
    window_.front().preint.reset();
    if (kept) {
      info->remapBlocks(remap);
      prior_ = info;
    } else {
      prior_.reset();
    }
  } else {
    // The newest-but-one frame is not a keyframe: drop its visual measurements, merge its IMU
    // interval into the next one, and remove its pose from the prior if the prior holds it.
    Slot& s1 = window_[N - 1];
    if (prior_ && priorTouches(s1.pose)) {
      auto info = std::make_shared<MarginalizationInfo>();
      info->add({std::make_shared<MarginalizationFactor>(prior_), nullptr, prior_->keptBlocks()});
      if (info->marginalize({s1.pose}, constant)) {
        prior_ = info;
      } else {
        prior_.reset();
      }
    }
    remap[window_[N].pose] = window_[N - 1].pose;
    remap[window_[N].sb] = window_[N - 1].sb;
    dropSecondNewestSlot();
    if (prior_) prior_->remapBlocks(remap);
  }
  out->ms_marginalisation = msSince(t0);
  stats_.sum_ms_marginalisation += out->ms_marginalisation;
}

void SlidingWindowEstimator::dropSecondNewestSlot() {
  const size_t N = window_.size() - 1;
  Slot& s1 = window_[N - 1];
  // Merge pre-integrations: (N-2 -> N-1) followed by (N-1 -> N).
  auto merged = std::make_unique<imu::Preintegration>(s1.preint->biasAcc(), s1.preint->biasGyr(),
                                                      imu::ImuNoise::fromOptions(imu_opt_));
  for (const auto& m : s1.preint->samples()) merged->push(m);
  const auto& next = window_[N].preint->samples();
  for (size_t k = 1; k < next.size(); ++k) merged->push(next[k]);
  window_[N].preint = std::move(merged);
  window_[N].bridged_s += s1.bridged_s;
  features_.removeSlot(static_cast<int>(N) - 1);
  window_.erase(window_.begin() + static_cast<std::ptrdiff_t>(N) - 1);
}

std::vector<KeyframeState> SlidingWindowEstimator::takeFinishedKeyframes() {
  std::vector<KeyframeState> out;
  out.swap(finished_keyframes_);
  return out;
}

std::vector<KeyframeState> SlidingWindowEstimator::windowKeyframes() const {
  std::vector<KeyframeState> out;
  if (status_ != EstimatorStatus::kTracking) return out;
  for (const auto& s : window_) out.push_back({s.t, s.T(), s.frame_index, segment_, s.bridged_s});
  return out;
}

}  // namespace rgbdi::estimator
