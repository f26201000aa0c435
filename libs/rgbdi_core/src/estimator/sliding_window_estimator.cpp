// The estimator's frame step: starting (static, depth-aided or visual start), tracking (a slot
// per frame that sees, the IMU across blind frames), solving, failure checks and resets, and
// sliding the window. The work itself is done by the collaborators in Parts.
#include "rgbdi/estimator/sliding_window_estimator.h"

#include <algorithm>
#include <string>

#include "estimator/depth_aided_start.h"
#include "estimator/failure_check.h"
#include "estimator/frame_window.h"
#include "estimator/static_start.h"
#include "estimator/visual_start.h"
#include "estimator/wheel_dead_reckoning.h"
#include "estimator/window_cost_model.h"
#include "estimator/window_ground_plane.h"
#include "estimator/window_marginalisation.h"
#include "estimator/window_motion_field.h"
#include "estimator/window_optimisation.h"
#include "estimator/window_start.h"
#include "estimator/window_state.h"
#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/estimator/initializer.h"
#include "rgbdi/imu/imu_buffer.h"
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

/// Stage timings are thread CPU time: on a shared machine wall time mostly measures the others.
double msSince(double cpu_t0_s) { return 1e3 * (threadCpuSeconds() - cpu_t0_s); }

}  // namespace

struct SlidingWindowEstimator::Parts {
  Parts(const EstimatorOptions& opt, const ImuOptions& imu_opt, const ExtrinsicOptions& ext)
      : model(opt, imu_opt, ext),
        window(opt, imu_opt, ext.time_offset_s),
        optimisation(opt, model),
        static_start(opt, imu_opt) {
    depth_check.tolerance_norm = opt.depth_verify_tolerance_px / EstimatorOptions::kVirtualFocalPx;
    depth_check.min_depth_m = opt.depth_verify_min_m;
    depth_check.max_depth_m = opt.depth_verify_max_m;
    depth_check.hold_constant = opt.verified_depth == "constant";
  }

  imu::ImuBuffer imu;
  WindowCostModel model;
  WindowState window;
  WindowOptimisation optimisation;
  StaticStart static_start;
  DepthCheckOptions depth_check;  ///< depth verification and triangulation of the tracks
};

SlidingWindowEstimator::SlidingWindowEstimator(const EstimatorOptions& opt, const ImuOptions& imu,
                                               const ExtrinsicOptions& ext)
    : mrpt::system::COutputLogger("rgbdi.estimator"),
      opt_(opt),
      imu_opt_(imu),
      parts_(std::make_unique<Parts>(opt, imu, ext)) {}

SlidingWindowEstimator::~SlidingWindowEstimator() = default;

void SlidingWindowEstimator::feedImu(const ImuSample& s) {
  imu::ImuBuffer& imu = parts_->imu;
  if (!imu.empty() && s.t <= imu.newestTime()) return;  // the stream stage already reports these
  imu.push(s);
}

void SlidingWindowEstimator::feedWheel(const WheelOdometrySample& w) {
  if (!opt_.wheel.enable) return;
  WindowWheels& wheels = parts_->window.wheels;
  wheels.add(w);
  // Nothing before the oldest frame is needed (without frames: nothing before the newest).
  const FrameWindow& window = parts_->window.frames;
  double keep_from = window.empty() ? w.t + wheels.time_offset[0] : window.front().t;
  // While starting, the start from the wheels looks back over its window.
  if (status_ != EstimatorStatus::kTracking && opt_.wheel.start_from_wheels)
    keep_from = std::min(keep_from, w.t + wheels.time_offset[0] - wheelStartHistory_s());
  wheels.trimBefore(keep_from, opt_.wheel);
}

double SlidingWindowEstimator::latestImuTime() const {
  return parts_->imu.empty() ? -1e300 : parts_->imu.newestTime();
}

double SlidingWindowEstimator::timeOffset() const { return parts_->window.time_offset[0]; }

void SlidingWindowEstimator::setRollingShutter(const RollingShutter& rs) {
  parts_->window.frames.setRollingShutter(rs);
  parts_->window.readout[0] = rs.readout_s;
  parts_->window.readout_prior_mean_s = rs.readout_s;
}

double SlidingWindowEstimator::rollingShutterReadout() const { return parts_->window.readout[0]; }

Eigen::Vector3d SlidingWindowEstimator::gyroBias() const {
  const FrameWindow& window = parts_->window.frames;
  return window.empty() ? Eigen::Vector3d::Zero() : window.back().bg();
}

void SlidingWindowEstimator::assignMotionFieldVelocities(std::size_t slot) {
  if (opt_.time_offset_velocity != "motion_field") return;
  estimator::assignMotionFieldVelocities(parts_->window.frames, slot, parts_->imu,
                                         parts_->model.T_body_cam);
}

void SlidingWindowEstimator::addSlot(const frontend::FeatureFrame& frame, double t,
                                     bool predict_from_previous) {
  FrameWindow& window = parts_->window.frames;
  last_preintegration_ms_ = window.add(frame, t, parts_->window.time_offset[0], parts_->imu,
                                       predict_from_previous, bridging_, parts_->model.T_body_cam);
  bridging_ = false;
  if (predict_from_previous) assignMotionFieldVelocities(window.size() - 1);
  // Keep what the window needs, and enough history for the stillness test of initialisation:
  // while initialising, back to the oldest stillness frame (the test may judge stillness since
  // the previous frame, however long ago that was).
  double keep_from = std::min(window.front().t, t - 2.0 * opt_.init_static_window_s);
  if (status_ != EstimatorStatus::kTracking && !parts_->static_start.empty())
    keep_from = std::min(keep_from, parts_->static_start.oldestFrameTime());
  // The start from the wheels and the ground plane's gate look back over their window.
  if (opt_.wheel.enable &&
      ((status_ != EstimatorStatus::kTracking && opt_.wheel.start_from_wheels) ||
       opt_.wheel.ground_plane_sigma_m > 0.0))
    keep_from = std::min(keep_from, t - wheelStartHistory_s());
  parts_->imu.popOlderThan(keep_from);
  stats_.sum_ms_preintegration += last_preintegration_ms_;
}

double SlidingWindowEstimator::wheelStartHistory_s() const {
  return opt_.wheel.start_window_s + opt_.wheel.reading_lag_s;
}

void SlidingWindowEstimator::countStartWait(const char* path, const char* why) {
  logFmt(mrpt::system::LVL_DEBUG, "initialisation not yet possible: %s\n", why);
  ++stats_.init_waits[std::string(path) + why];
}

bool SlidingWindowEstimator::tryStart(const frontend::FeatureFrame& frame, double t) {
  WindowState& state = parts_->window;
  FrameWindow& window = state.frames;
  const Eigen::Isometry3d& T_bc = parts_->model.T_body_cam;
  const Eigen::Vector3d p0 = have_anchor_ ? anchor_p_ : Eigen::Vector3d::Zero();
  const double yaw0 = have_anchor_ ? anchor_yaw_ : 0.0;
  parts_->static_start.addFrame(t, frame.features);
  if (opt_.init_allow_static) {
    const Stillness still = parts_->static_start.judge(frame, t, parts_->imu);
    if (!still.failure) {
      window.clear();
      state.prior.reset();
      state.wheels.priorDropped();
      addSlot(frame, t, false);
      adoptRestingStart(state, still, p0, yaw0, opt_);
      ++stats_.static_initialisations;
      return true;
    }
    countStartWait("static start: ", still.failure);
  }
  if (opt_.wheel.enable && opt_.wheel.start_from_wheels &&
      static_cast<int>(frame.features.size()) >= opt_.fail_min_features) {
    // Moving (or vibrating): the wheels know the velocity, so the IMU knows gravity.
    const WindowWheels& wheels = state.wheels;
    const WheelStart ws = solveWheelStart(wheels.readings, wheels.calibration(opt_.wheel),
                                          parts_->imu, t, imu_opt_.gravity_m_s2, opt_.wheel);
    if (!ws.failure) {
      window.clear();
      state.prior.reset();
      state.wheels.priorDropped();
      addSlot(frame, t, false);
      adoptWheelStart(state, ws, p0, yaw0, opt_);
      ++stats_.wheel_initialisations;
      return true;
    }
    countStartWait("wheel start: ", ws.failure);
  }
  addSlot(frame, t, false);
  // Frames without (enough) depth, e.g. --no-depth: the visual SfM start.
  const bool visual = !newestSlotHasDepthForPnp(window, opt_);
  const MovingStart moving =
      visual ? solveVisualStart(window, opt_, imu_opt_, T_bc, *this)
             : solveDepthAidedStart(window, state.time_offset[0], opt_, imu_opt_, T_bc, *this);
  if (!moving.failure) {
    adoptMovingStart(state, moving, p0, yaw0, opt_);
    ++stats_.moving_initialisations;
    if (visual) ++stats_.visual_initialisations;
    return true;
  }
  countStartWait("moving start: ", moving.failure);
  if (visual && window.size() >= 3 && !window.newestButOneIsKeyframe()) {
    // The SfM window holds keyframes (enough parallax between them), as the sliding window
    // does, so that it spans enough time for the scale to be observable.
    window.dropSecondNewest();
  }
  // Keep the initialisation window bounded: forget the oldest frame.
  if (static_cast<int>(window.size()) > opt_.window_size) window.removeOldest(T_bc);
  return false;
}

bool SlidingWindowEstimator::start(const frontend::FeatureFrame& frame, double t,
                                   FrameEstimate& out) {
  if (!tryStart(frame, t)) return false;
  FrameWindow& window = parts_->window.frames;
  status_ = EstimatorStatus::kTracking;
  last_sighted_t_ = frame.t;
  out.just_initialised = true;
  parts_->window.prior.reset();
  parts_->window.wheels.priorDropped();
  window.features().updateDepths(window.poses(), parts_->model.T_body_cam, parts_->depth_check);
  for (std::size_t k = 0; k < window.size(); ++k) assignMotionFieldVelocities(k);
  if (window.size() >= 2) optimise(&out, false);
  return true;
}

void SlidingWindowEstimator::propagateWithImu(double t, FrameEstimate& out) {
  const double t0 = threadCpuSeconds();
  const WindowSlot& s = parts_->window.frames.back();
  imu::Preintegration pre(s.ba(), s.bg(), imu::ImuNoise::fromOptions(imu_opt_));
  for (const ImuSample& m : parts_->imu.between(s.t, t)) pre.push(m);
  Eigen::Vector3d P, V;
  Eigen::Quaterniond Q;
  pre.predict(s.p(), s.q(), s.v(), Eigen::Vector3d(0, 0, -imu_opt_.gravity_m_s2), P, Q, V);
  out.has_pose = true;
  out.T_world_body.linear() = Q.normalized().toRotationMatrix();
  out.T_world_body.translation() = P;
  out.v_world = V;
  out.bias_acc = s.ba();
  out.bias_gyr = s.bg();
  out.time_offset_s = parts_->window.time_offset[0];
  out.rolling_shutter_readout_s = parts_->window.readout[0];
  out.ms_preintegration = msSince(t0);
  stats_.sum_ms_preintegration += out.ms_preintegration;
}

bool SlidingWindowEstimator::track(const frontend::FeatureFrame& frame, double t,
                                   FrameEstimate& out) {
  FrameWindow& window = parts_->window.frames;
  const Eigen::Isometry3d& T_bc = parts_->model.T_body_cam;
  out.blind = static_cast<int>(frame.features.size()) < opt_.fail_min_features;
  // Image stamps, not IMU-clock times: the time-offset estimate moves between the two frames
  // and would decide a blackout of exactly fail_max_blind_s (a whole number of frame periods)
  // by its last digits; the tolerance keeps round-off of the stamps out of it too.
  constexpr double kStampTolerance_s = 1e-3;
  // With the wheels fused and their readings up to this frame, blind frames are carried by the
  // IMU and the wheels for up to [wheel] max_blind_s.
  const WheelOptions& wheel_opt = opt_.wheel;
  const bool wheels_carry =
      out.blind && wheel_opt.enable && wheel_opt.max_blind_s > opt_.fail_max_blind_s &&
      !parts_->window.wheels.readings.empty() &&
      parts_->window.wheels.readings.back().t + parts_->window.wheels.time_offset[0] >=
          t - wheel_opt.reading_lag_s;
  const double max_blind_s = wheels_carry ? wheel_opt.max_blind_s : opt_.fail_max_blind_s;
  if (!out.blind) {
    last_sighted_t_ = frame.t;
  } else if (opt_.fail_max_blind_s > 0.0 &&
             frame.t - last_sighted_t_ > max_blind_s + kStampTolerance_s) {
    logFmt(mrpt::system::LVL_WARN,
           "t=%.3f: fewer than %d features for %.2f s: tracking lost, re-initialising\n", t,
           opt_.fail_min_features, frame.t - last_sighted_t_);
    ++stats_.resets;
    ++stats_.blind_resets;
    reset(true);
    out.reset = true;
    return false;
  }
  // Blind frames get no slot: their pose is the IMU propagation of the newest sighted state,
  // and the window keeps the frames that saw something. The first frame that sees again joins
  // it through one pre-integration over the whole blind interval, so velocity and biases stay
  // held by the features seen before it (a window of featureless slots would leave them to
  // the IMU alone, and from there the estimate was seen to drift away after the images came
  // back), and the new frame's depth-verified features fix its position against them.
  const bool between_updates =
      opt_.update_rate_hz > 0.0 && t - window.back().t < 0.9 / opt_.update_rate_hz;
  bridging_ = bridging_ || out.blind;
  if (out.blind || between_updates) {
    // Also between estimator updates (update_rate_hz): the IMU propagation of the newest slot.
    propagateWithImu(t, out);
    if (out.blind && wheel_opt.enable) {
      // The position from the wheels (the IMU alone drifts by its velocity error).
      const WindowSlot& s = window.back();
      if (const auto dr = wheelInertialDeadReckoning(parts_->window.wheels, wheel_opt,
                                                     parts_->imu.between(s.t, t), s.bg(), s.t,
                                                     s.p(), s.q(), t)) {
        out.T_world_body.translation() = dr->p_world_body;
        out.v_world = dr->v_world;
      }
    }
    return false;
  }
  const bool after_blind = bridging_;
  addSlot(frame, t, true);
  if (after_blind && wheel_opt.enable && window.size() >= 2) {
    // The first frame that sees again starts from the wheels' position, not the IMU's: the
    // solve (and the gate of the wheel factor over the blind interval) starts near the truth.
    const WindowSlot& prev = window[window.size() - 2];
    WindowSlot& s = window.back();
    if (const auto dr = wheelInertialDeadReckoning(parts_->window.wheels, wheel_opt,
                                                   parts_->imu.between(prev.t, t), prev.bg(),
                                                   prev.t, prev.p(), prev.q(), t)) {
      s.setPose(dr->p_world_body, s.q());
      s.setV(dr->v_world);
    }
  }
  out.ms_preintegration = last_preintegration_ms_;
  // The second-newest frame leaves the window after this update unless it is a keyframe.
  const bool leaving =
      !window.newestButOneIsKeyframe() && static_cast<int>(window.size()) > opt_.window_size;
  optimise(&out, leaving && opt_.non_keyframe_update == "single_step");
  if (const char* why = failureReason(window, prev_newest_p_, prev_newest_t_, opt_)) {
    logFmt(mrpt::system::LVL_WARN, "failure detected at t=%.3f (%s): re-initialising\n", t, why);
    ++stats_.resets;
    reset(true);
    out.reset = true;
    return false;
  }
  window.rejectOutliers(opt_.outlier_reprojection_px / EstimatorOptions::kVirtualFocalPx, T_bc);
  // Depth verification and triangulation use the optimised poses (never the IMU-only
  // prediction of the newest frame): a verified depth is held constant afterwards, so any
  // pose error baked into it would persist.
  window.features().updateDepths(window.poses(), T_bc, parts_->depth_check);
  if (static_cast<int>(window.size()) > opt_.window_size) {
    marginaliseAndSlide(window.newestButOneIsKeyframe(), &out);
  }
  return true;
}

FrameEstimate SlidingWindowEstimator::processFrame(const frontend::FeatureFrame& frame) {
  const FrameWindow& window = parts_->window.frames;
  FrameEstimate out;
  out.t_image = frame.t;
  const double t = frame.t + parts_->window.time_offset[0];
  out.t_imu = t;
  ++stats_.frames;
  if (!window.empty() && t <= window.back().t) return out;  // stale frame: ignore
  if (!parts_->imu.covers(window.empty() ? t : window.back().t, t)) {
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
  const bool updated =
      status_ == EstimatorStatus::kTracking ? track(frame, t, out) : start(frame, t, out);
  out.status = status_;
  if (!updated) return out;

  const WindowSlot& s = window.back();
  out.has_pose = true;
  out.T_world_body = s.T();
  out.v_world = s.v();
  out.bias_acc = s.ba();
  out.bias_gyr = s.bg();
  out.time_offset_s = parts_->window.time_offset[0];
  out.rolling_shutter_readout_s = parts_->window.readout[0];
  out.t_imu = s.t;
  prev_newest_p_ = s.p();
  prev_newest_t_ = s.t;
  have_anchor_ = true;
  anchor_p_ = s.p();
  anchor_yaw_ = yawOf(s.T().rotation());
  last_good_window_ = window.keyframeStates(segment_, &parts_->imu);
  if (stats_.first_pose_t_image < 0.0) stats_.first_pose_t_image = frame.t;
  return out;
}

void SlidingWindowEstimator::optimise(FrameEstimate* out, bool single_step) {
  const double t0 = threadCpuSeconds();
  if (opt_.wheel.enable && opt_.wheel.ground_plane_sigma_m > 0.0)
    judgeNewFrames(parts_->window, parts_->imu, opt_.wheel, imu_opt_.gravity_m_s2);
  const WindowUpdate update = parts_->optimisation.run(parts_->window, single_step);
  if (opt_.estimate_rolling_shutter_readout) {
    // The observations to come are moved to their stamps with the new estimate.
    RollingShutter rs = parts_->window.frames.rollingShutter();
    rs.readout_s = parts_->window.readout[0];
    parts_->window.frames.setRollingShutter(rs);
  }
  if (update.single_step) ++stats_.single_step_updates;
  ++stats_.optimisations;
  stats_.solver_iterations += update.summary.successful_steps + update.summary.unsuccessful_steps;
  if (update.summary.termination == WindowSolverSummary::Termination::kNoConvergence)
    ++stats_.solver_iterations_capped;
  stats_.solver_factorisation_retries += update.summary.factorisation_retries;
  stats_.wheel_factors_solved += update.n_wheel_factors;
  out->n_features_used = update.n_features_used;
  out->n_depth_verified = update.n_depth_verified;
  out->ms_optimisation = msSince(t0);
  stats_.sum_ms_optimisation += out->ms_optimisation;
}

void SlidingWindowEstimator::marginaliseAndSlide(bool newest_but_one_is_keyframe,
                                                 FrameEstimate* out) {
  const double t0 = threadCpuSeconds();
  if (newest_but_one_is_keyframe) {
    // The leaving keyframe's motion, while its slot and the IMU at its time are still there.
    const KeyframeState motion = parts_->window.frames.keyframeStates(segment_, &parts_->imu)[0];
    KeyframeState leaving = marginaliseOldestSlot(parts_->window, parts_->model, segment_);
    leaving.v_world = motion.v_world;
    leaving.omega_body = motion.omega_body;
    leaving.rolling_shutter_readout_s = motion.rolling_shutter_readout_s;
    finished_keyframes_.push_back(leaving);
  } else
    dropSecondNewestSlot(parts_->window, parts_->model);
  out->ms_marginalisation = msSince(t0);
  stats_.sum_ms_marginalisation += out->ms_marginalisation;
  const WindowWheels& wheels = parts_->window.wheels;
  stats_.wheel_intervals_used = wheels.intervals_used;
  stats_.wheel_intervals_gap = wheels.intervals_gap;
  stats_.wheel_intervals_slip = wheels.intervals_slip;
  stats_.wheel_intervals_stuck = wheels.intervals_stuck;
  stats_.wheel_intervals_lifted = wheels.intervals_lifted;
  stats_.wheel_factors_gated = wheels.factors_gated;
  stats_.ground_plane_used = wheels.ground_plane_used;
  stats_.ground_plane_gated = wheels.ground_plane_gated;
  if (stats_.wheel_fault_episodes.size() != wheels.episodes.size() ||
      (!wheels.episodes.empty() &&
       stats_.wheel_fault_episodes.back().t_end != wheels.episodes.back().t_end)) {
    stats_.wheel_fault_episodes.clear();
    for (const auto& e : wheels.episodes)
      stats_.wheel_fault_episodes.push_back({e.t_start, e.t_end,
                                             e.verdict == WheelVerdict::Stuck    ? "stuck"
                                             : e.verdict == WheelVerdict::Lifted ? "lifted"
                                                                                 : "slip"});
  }
  stats_.wheel_scale_v = wheels.scale_v[0];
  stats_.wheel_scale_w = wheels.scale_w[0];
  stats_.wheel_extrinsic_yaw_rad = wheels.extrinsic_yaw[0];
  stats_.wheel_time_offset_s = wheels.time_offset[0];
}

void SlidingWindowEstimator::reset(bool keep_anchor) {
  finished_keyframes_.insert(finished_keyframes_.end(), last_good_window_.begin(),
                             last_good_window_.end());
  last_good_window_.clear();
  if (status_ == EstimatorStatus::kTracking) ++segment_;
  if (!keep_anchor) have_anchor_ = false;
  parts_->window.frames.clear();
  parts_->window.prior.reset();
  parts_->window.wheels.priorDropped();
  parts_->window.start_prior.active = false;
  parts_->static_start.clear();
  bridging_ = false;
  status_ = EstimatorStatus::kInitializing;
}

std::vector<KeyframeState> SlidingWindowEstimator::takeFinishedKeyframes() {
  std::vector<KeyframeState> out;
  out.swap(finished_keyframes_);
  return out;
}

std::vector<KeyframeState> SlidingWindowEstimator::windowKeyframes() const {
  if (status_ != EstimatorStatus::kTracking) return {};
  return parts_->window.frames.keyframeStates(segment_, &parts_->imu);
}

}  // namespace rgbdi::estimator
