#include "rgbdi/system/vio_system.h"

#include <algorithm>
#include <optional>
#include <unordered_set>

#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/common/motion_field.h"
#include "rgbdi/imu/gyro_rotation.h"

namespace rgbdi::system {

namespace {
// Frames waiting for IMU beyond this many are dropped (an IMU stream that stopped): bounded memory.
constexpr std::size_t kMaxPendingFrames = 64;
// [s] IMU kept for the rotation prediction when no image arrives (an image stream that
// stopped): bounded memory; an image after a longer gap is predicted with held rates.
constexpr double kMaxGyroHistory_s = 2.0;
}  // namespace

VioSystem::VioSystem(const SystemConfig& cfg, bool use_depth)
    : cfg_(cfg),
      use_depth_(use_depth),
      estimator_(std::make_unique<estimator::SlidingWindowEstimator>(cfg.estimator, cfg.imu,
                                                                     cfg.extrinsic)) {
  estimator_->setRollingShutter(cfg.camera.rollingShutter());
}

VioSystem::~VioSystem() = default;

PinholeCamera VioSystem::cameraFor(const RgbdFrame& frame) const {
  if (cfg_.camera.intrinsics_source == "stream" && frame.cam_color.valid()) return frame.cam_color;
  return cfg_.camera.camera;
}

void VioSystem::feedWheel(const WheelOdometrySample& wheel) { estimator_->feedWheel(wheel); }

void VioSystem::feedImu(const ImuSample& imu) {
  estimator_->feedImu(imu);
  if (gyro_history_.empty() || imu.t > gyro_history_.newestTime()) {
    gyro_history_.push(imu);
    if (imu.t - gyro_history_.oldestTime() > kMaxGyroHistory_s)
      gyro_history_.popOlderThan(imu.t - kMaxGyroHistory_s);
  }
  processReady(false);
}

void VioSystem::feedRgbd(const RgbdFrame& frame) { track(frame, nullptr); }

void VioSystem::feedRgbd(const RgbdFrame& frame, const frontend::PreparedImage& prepared) {
  track(frame, &prepared);
}

void VioSystem::track(const RgbdFrame& in, const frontend::PreparedImage* prepared) {
  ++frames_received_;
  if (!in.hasColor()) {  // depth-only frames cannot be tracked
    ++frames_dropped_;
    return;
  }
  if (!tracker_) {
    tracker_ = std::make_unique<frontend::FeatureTracker>(cfg_.frontend, cameraFor(in));
    tracker_->setRollingShutter(cfg_.camera.rollingShutter());
  }
  if (cfg_.estimator.estimate_rolling_shutter_readout) {
    // The depth of each feature is read at its stamp position with the newest readout estimate.
    RollingShutter rs = cfg_.camera.rollingShutter();
    rs.readout_s = estimator_->rollingShutterReadout();
    tracker_->setRollingShutter(rs);
  }
  Pending p;
  p.frame = in;
  if (!use_depth_) p.frame.depth.release();
  // Thread CPU time, like the estimator's stages: on a shared machine wall time mostly measures
  // the other processes.
  // An image prepared ahead was prepared on another thread: its CPU counts as tracking too.
  const double t0 = threadCpuSeconds() - (prepared ? 1e-3 * prepared->cpuMs() : 0.0);
  std::optional<frontend::CameraMotion> motion;
  if (has_tracked_ && cfg_.frontend.klt_predict_rotation)
    motion = cameraMotion(last_tracked_t_, in.t);
  p.features = tracker_->track(p.frame, motion, prepared);
  last_tracked_t_ = in.t;
  has_tracked_ = true;
  // The next prediction starts at this image.
  if (!gyro_history_.empty()) gyro_history_.popOlderThan(in.t + estimator_->timeOffset());
  timings_.tracking_ms += 1e3 * (threadCpuSeconds() - t0);
  ++timings_.frames_tracked;
  pending_.push_back(std::move(p));
  while (pending_.size() > kMaxPendingFrames) {
    pending_.pop_front();
    ++frames_dropped_;
  }
  processReady(false);
}

frontend::CameraMotion VioSystem::cameraMotion(double t0, double t1) const {
  const double td = estimator_->timeOffset();
  const Eigen::Isometry3d& T_bc = cfg_.extrinsic.T_body_cam;
  const Eigen::Matrix3d R_cb = T_bc.linear().transpose();
  // The rate at this image's stamp, for the rolling-shutter shift of its rows.
  const Eigen::Vector3d omega_body = imu::gyroRate(gyro_history_, t1 + td, estimator_->gyroBias());
  // Dead reckoning needs the velocity at t0: the estimate of the image at t0, when that image was
  // estimated before this one arrived (the IMU passed it) and has a pose.
  const bool velocity_known = cfg_.frontend.klt_predict_translation && newest_estimate_ &&
                              newest_estimate_->has_pose && newest_estimate_->t_image == t0;
  if (!velocity_known) {
    const Eigen::Matrix3d R_body =
        imu::gyroRotation(gyro_history_, t0 + td, t1 + td, estimator_->gyroBias())
            .toRotationMatrix();
    frontend::CameraMotion m(R_cb * R_body * T_bc.linear());
    m.omega_cam = R_cb * omega_body;
    return m;
  }
  const estimator::FrameEstimate& e = *newest_estimate_;
  imu::BodyState start, end;
  start.q_world_body = Eigen::Quaterniond(e.T_world_body.linear());
  start.v_world = e.v_world;
  start.bias_gyr = e.bias_gyr;
  start.bias_acc = e.bias_acc;
  const Eigen::Isometry3d T_b0_b1 =
      imu::deadReckonedMotion(gyro_history_, e.t_imu, t1 + td, start,
                              Eigen::Vector3d(0.0, 0.0, -cfg_.imu.gravity_m_s2), &end);
  const Eigen::Isometry3d T_c0_c1 = T_bc.inverse() * T_b0_b1 * T_bc;
  frontend::CameraMotion m(T_c0_c1.linear(), T_c0_c1.translation());
  const CameraVelocity c =
      cameraVelocity(T_bc, end.q_world_body.conjugate() * end.v_world, omega_body);
  m.omega_cam = c.omega_cam;
  m.v_cam = c.v_cam;
  return m;
}

void VioSystem::endOfStream() {
  processReady(true);
  emitKeyframes(estimator_->windowKeyframes());
  frames_dropped_ += pending_.size();
  pending_.clear();
  // Nothing leaves the window any more: the images kept for that (about a dozen frames, 15 MB
  // at 640x480) and the tracker's pyramids are released before the outputs are written.
  recent_frames_ = {};
  if (tracker_) tracker_->reset();  // none when no image arrived
}

void VioSystem::processReady(bool flush) {
  while (!pending_.empty()) {
    Pending& p = pending_.front();
    const double t_needed = p.features.t + estimator_->timeOffset();
    // Wait until the IMU has passed the frame time (interpolation needs a sample after it).
    if (estimator_->latestImuTime() < t_needed) {
      if (!flush) return;
      break;
    }
    const estimator::FrameEstimate est = estimator_->processFrame(p.features);
    newest_estimate_ = est;
    timings_.preintegration_ms += est.ms_preintegration;
    timings_.optimisation_ms += est.ms_optimisation;
    timings_.marginalisation_ms += est.ms_marginalisation;
    ++timings_.frames_estimated;
    if (est.has_pose && cfg_.estimator.estimate_rolling_shutter_readout &&
        (readout_history_.empty() || est.t_image >= readout_history_.back().first + 1.0))
      readout_history_.emplace_back(est.t_image, est.rolling_shutter_readout_s);
    if (est.has_pose) {
      traj_body_.push_back(StampedPose::fromIsometry(est.t_imu, est.T_world_body));
      traj_cam_.push_back(
          StampedPose::fromIsometry(est.t_image, est.T_world_body * cfg_.extrinsic.T_body_cam));
    }
    if (frame_cb_) frame_cb_(est, p.frame);
    recent_frames_.push_back(std::move(p));
    pending_.pop_front();
    emitKeyframes(estimator_->takeFinishedKeyframes());
    emitEarlyKeyframes();
    // Only frames that are window slots can still become keyframes: keep their images and
    // nothing else (the window may span many seconds when the robot moves slowly, so keeping
    // every frame since the oldest slot would grow memory with time).
    std::unordered_set<std::uint64_t> slots;
    for (const auto& w : estimator_->windowKeyframes()) slots.insert(w.frame_index);
    recent_frames_.erase(
        std::remove_if(recent_frames_.begin(), recent_frames_.end(),
                       [&](const Pending& f) { return !slots.count(f.frame.index); }),
        recent_frames_.end());
  }
}

const VioSystem::Pending* VioSystem::recentFrame(std::uint64_t frame_index) const {
  for (const auto& f : recent_frames_)
    if (f.frame.index == frame_index) return &f;
  return nullptr;
}

void VioSystem::emitKeyframes(std::vector<estimator::KeyframeState> kfs) {
  for (auto& kf : kfs) {
    keyframes_.push_back(kf);
    if (!keyframe_cb_) continue;
    if (const Pending* f = recentFrame(kf.frame_index)) keyframe_cb_(kf, f->frame, f->features);
  }
}

void VioSystem::emitEarlyKeyframes() {
  if (!early_wanted_ || !keyframe_cb_) return;
  const std::vector<estimator::KeyframeState> window = estimator_->windowKeyframes();
  // The newest slot and the one before it may still be dropped (not a keyframe after all).
  if (window.size() < 3 || !early_wanted_(window.front().segment)) return;
  for (std::size_t i = 0; i + 2 < window.size(); ++i) {
    const estimator::KeyframeState& kf = window[i];
    if (kf.t_imu <= last_early_t_) continue;
    last_early_t_ = kf.t_imu;
    if (const Pending* f = recentFrame(kf.frame_index)) keyframe_cb_(kf, f->frame, f->features);
  }
}

}  // namespace rgbdi::system
