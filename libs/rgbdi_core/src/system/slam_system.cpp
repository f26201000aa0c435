#include "rgbdi/system/slam_system.h"

#include <algorithm>

#include "rgbdi/io/mrpt_conversions.h"

namespace rgbdi::system {

namespace {
/// Images handed to another thread must not share memory with buffers a source may reuse.
RgbdFrame ownedCopy(const RgbdFrame& in) {
  RgbdFrame f = in;
  f.rgb = in.rgb.clone();
  f.depth = in.depth.clone();
  return f;
}
}  // namespace

SlamSystem::SlamSystem(const SystemConfig& cfg, const SlamSystemOptions& options)
    : cfg_(cfg),
      options_(options),
      vio_(cfg, options.use_depth),
      mapper_(std::make_unique<mapping::Mapper>(cfg.mapping, cfg.output.write_octomap)) {
  vio_.setFrameCallback(
      [this](const estimator::FrameEstimate& est, const RgbdFrame& f) { onFrame(est, f); });
  vio_.setKeyframeCallback([this](const estimator::KeyframeState& kf, const RgbdFrame& f,
                                  const frontend::FeatureFrame& ff) { onKeyframe(kf, f, ff); });
  const bool t = options.threaded;
  const std::size_t cap = options.queue_capacity;
  map_stage_ = std::make_unique<StageWorker<MapPacket>>(
      "mapping", [this](MapPacket& p) { handleMap(p); }, t, cap);
  loop_stage_ = std::make_unique<StageWorker<KeyframePacket>>(
      "loop closing", [this](KeyframePacket& p) { handleKeyframe(p); }, t, cap);
  odometry_stage_ = std::make_unique<StageWorker<io::Measurement>>(
      "odometry", [this](io::Measurement& m) { handleMeasurement(m); }, t, cap);
}

SlamSystem::~SlamSystem() = default;

void SlamSystem::feedImu(const ImuSample& imu) { odometry_stage_->submit(imu); }

void SlamSystem::feedRgbd(const RgbdFrame& frame) {
  odometry_stage_->submit(options_.threaded ? ownedCopy(frame) : frame);
}

void SlamSystem::endOfStream() {
  if (ended_) return;
  ended_ = true;
  odometry_stage_->finish();
  vio_.endOfStream();  // flushes the window: its keyframes go to loop closing
  loop_stage_->finish();
  map_stage_->finish();
  mapper_->finish();
  final_keyframe_poses_.clear();
  for (const KeyframePacket& k : keyframe_states_)
    final_keyframe_poses_.push_back(k.state.T_world_body);
}

void SlamSystem::handleMeasurement(io::Measurement& m) {
  if (auto* imu = std::get_if<ImuSample>(&m)) {
    vio_.feedImu(*imu);
  } else {
    vio_.feedRgbd(std::get<RgbdFrame>(m));
    progress_frames_.store(vio_.framesReceived());
    progress_status_.store(static_cast<int>(vio_.status()));
  }
}

void SlamSystem::onFrame(const estimator::FrameEstimate& est, const RgbdFrame&) {
  if (est.reset) ++frame_segment_;  // the estimator starts a new segment at every reset
  if (!est.has_pose) return;
  FrameRecord r;
  r.t_imu = est.t_imu;
  r.t_image = est.t_image;
  r.segment = frame_segment_;
  r.T_world_body_odom = est.T_world_body;
  r.T_world_body_online = onlineDrift(frame_segment_) * est.T_world_body;
  frames_.push_back(r);
}

Eigen::Isometry3d SlamSystem::onlineDrift(int segment) {
  const std::size_t lag = 1;
  const std::size_t emitted = keyframe_states_.size();
  std::size_t entry;  // drift entry to use: after keyframe `entry - 1` was handled
  if (options_.live) {
    entry = loop_stage_->handled();
  } else {
    entry = emitted > lag ? emitted - lag : 0;
    loop_stage_->waitHandled(entry);
  }
  if (entry == 0) return Eigen::Isometry3d::Identity();
  std::lock_guard<std::mutex> lock(drift_mutex_);
  const auto& d = drift_after_keyframe_[entry - 1];
  return segment < static_cast<int>(d.size()) ? d[static_cast<std::size_t>(segment)]
                                              : Eigen::Isometry3d::Identity();
}

void SlamSystem::onKeyframe(const estimator::KeyframeState& kf, const RgbdFrame& frame,
                            const frontend::FeatureFrame& features) {
  if (kf.t_imu <= last_keyframe_t_) return;  // already handed out
  const Eigen::Vector3d p = kf.T_world_body.translation();
  if (kf.segment == last_keyframe_segment_) travelled_m_ += (p - last_keyframe_p_).norm();
  last_keyframe_t_ = kf.t_imu;
  last_keyframe_p_ = p;
  last_keyframe_segment_ = kf.segment;

  KeyframePacket packet;
  packet.id = keyframe_states_.size();
  packet.state = kf;
  packet.travelled_m = travelled_m_;
  KeyframePacket record = packet;  // without images: kept for the outputs
  record.features.features.clear();
  keyframe_states_.push_back(std::move(record));
  if (options_.keep_observations)
    observations_.push_back(io::toMrpt(frame, cfg_.extrinsic.T_body_cam, "RGBD"));
  packet.frame = frame;
  packet.features = features;
  progress_keyframes_.store(keyframe_states_.size());
  loop_stage_->submit(std::move(packet));
}

void SlamSystem::handleKeyframe(KeyframePacket& p) {
  const std::size_t n_segments = static_cast<std::size_t>(p.state.segment) + 1;
  std::vector<Eigen::Isometry3d> drift(n_segments, Eigen::Isometry3d::Identity());
  const Eigen::Isometry3d T_world_body =
      drift[static_cast<std::size_t>(p.state.segment)] * p.state.T_world_body;
  MapPacket m;
  m.keyframe.id = p.id;
  m.keyframe.frame_index = p.state.frame_index;
  m.keyframe.t = p.frame.t;
  m.keyframe.T_world_cam = T_world_body * cfg_.extrinsic.T_body_cam;
  for (const auto& f : p.features.features) {
    mapping::KeyframeFeature kfe;
    kfe.id = f.id;
    kfe.uv = f.uv;
    kfe.has_position = f.depth_m > 0.0;
    if (kfe.has_position) kfe.p_cam = Eigen::Vector3d(f.xn.x(), f.xn.y(), 1.0) * f.depth_m;
    m.keyframe.features.push_back(kfe);
  }
  m.frame = std::move(p.frame);
  map_stage_->submit(std::move(m));
  {
    std::lock_guard<std::mutex> lock(drift_mutex_);
    drift_after_keyframe_.push_back(std::move(drift));
  }
}

void SlamSystem::handleMap(MapPacket& p) {
  if (p.is_correction) {
    mapper_->correct(p.corrected_poses);
  } else {
    mapper_->addKeyframe(std::move(p.keyframe), p.frame);
  }
}

SlamProgress SlamSystem::progress() const {
  SlamProgress s;
  s.frames = progress_frames_.load();
  s.keyframes = progress_keyframes_.load();
  s.loops_accepted = progress_loops_.load();
  s.status = static_cast<estimator::EstimatorStatus>(progress_status_.load());
  return s;
}

Eigen::Isometry3d SlamSystem::keyframePose(std::size_t slot) const {
  return slot < final_keyframe_poses_.size() ? final_keyframe_poses_[slot]
                                             : keyframe_states_.at(slot).state.T_world_body;
}

Trajectory SlamSystem::odometryTrajectory() const {
  Trajectory t;
  t.reserve(frames_.size());
  for (const FrameRecord& r : frames_)
    t.push_back(StampedPose::fromIsometry(r.t_imu, r.T_world_body_odom));
  return t;
}

Trajectory SlamSystem::onlineTrajectory() const {
  Trajectory t;
  t.reserve(frames_.size());
  for (const FrameRecord& r : frames_)
    t.push_back(StampedPose::fromIsometry(r.t_imu, r.T_world_body_online));
  return t;
}

Trajectory SlamSystem::finalTrajectory() const {
  // Correction of each keyframe: final pose * odometry pose^-1; a frame takes the correction of
  // the keyframe of its segment nearest in time (none: its segment has no keyframe, odometry).
  Trajectory t;
  t.reserve(frames_.size());
  std::size_t k = 0;
  const std::size_t nk = keyframe_states_.size();
  for (const FrameRecord& r : frames_) {
    while (k + 1 < nk && (keyframe_states_[k + 1].state.segment < r.segment ||
                          (keyframe_states_[k + 1].state.segment == r.segment &&
                           keyframe_states_[k + 1].state.t_imu <= r.t_imu)))
      ++k;
    Eigen::Isometry3d D = Eigen::Isometry3d::Identity();
    // Candidates: keyframe k (at or before the frame) and k + 1 (after it), same segment only.
    std::size_t best = nk;
    double best_dt = 1e300;
    for (std::size_t c = k; c < std::min(nk, k + 2); ++c) {
      const auto& s = keyframe_states_[c].state;
      if (s.segment != r.segment) continue;
      const double dt = std::abs(s.t_imu - r.t_imu);
      if (dt < best_dt) {
        best_dt = dt;
        best = c;
      }
    }
    if (best < nk && best < final_keyframe_poses_.size())
      D = final_keyframe_poses_[best] * keyframe_states_[best].state.T_world_body.inverse();
    t.push_back(StampedPose::fromIsometry(r.t_imu, D * r.T_world_body_odom));
  }
  return t;
}

Trajectory SlamSystem::toCameraFrame(const Trajectory& body) const {
  // Camera poses carry the image stamps (camera clock): same order as frames_.
  Trajectory t;
  t.reserve(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    const double stamp = i < frames_.size() ? frames_[i].t_image : body[i].t;
    t.push_back(StampedPose::fromIsometry(stamp, body[i].isometry() * cfg_.extrinsic.T_body_cam));
  }
  return t;
}

}  // namespace rgbdi::system
