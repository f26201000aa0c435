#include "rgbdi/system/slam_system.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/motion_field.h"
#include "rgbdi/estimator/rolling_shutter_compensation.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/map/map_directory.h"

namespace rgbdi::system {

namespace {
/// Images handed to another thread must not share memory with buffers a source may reuse.
/// Images that are the frame's own (decoded from a file) are shared instead: a copy would keep
/// both alive while the frame waits in the queue (1.5 MB per 640x480 frame).
RgbdFrame ownedCopy(const RgbdFrame& in) {
  RgbdFrame f = in;
  if (in.images_exclusive) return f;
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
  if (options.map) {
    if (!cfg.loop.enable)
      throw std::invalid_argument(
          "a loaded map needs loop closure: [loop] enable = true (and no --no-loop)");
    id_offset_ = options.map->manifest.next_keyframe_id;
    segment_offset_ = 1;  // segment 0 is the map in the pose graph
    frame_segment_ = segment_offset_;
    progress_map_state_.store(static_cast<int>(MapState::kNotLocalised));
    mapper_->restore(options.map->keyframes);
    if (cfg.reloc.enable)
      geo_reloc_ = std::make_unique<GeoRelocStage>(cfg.reloc, options.map, cfg.extrinsic.T_body_cam,
                                                   options.threaded, options.live);
  }
  vio_.setFrameCallback(
      [this](const estimator::FrameEstimate& est, const RgbdFrame& f) { onFrame(est, f); });
  vio_.setKeyframeCallback([this](const estimator::KeyframeState& kf, const RgbdFrame& f,
                                  const frontend::FeatureFrame& ff) { onKeyframe(kf, f, ff); });
  frame_segment_placed_ = !options.map;  // a run without a map starts in the origin's frame
  if (cfg.loop.enable && cfg.loop.relocalize_from_window)
    vio_.setEarlyKeyframes([this](int estimator_segment) {
      return estimator_segment + segment_offset_ == frame_segment_ && !frame_segment_placed_;
    });
  // OpenCV's thread count is process-wide and must not change while another thread runs an
  // OpenCV operation: set it now, before the stages (and the feeding thread's image preparation)
  // use OpenCV; the tracker built later on the odometry thread then finds it set.
  frontend::applyOpenCvThreads(cfg.frontend);
  const bool t = options.threaded;
  const auto cap = static_cast<std::size_t>(cfg.pipeline.queue_capacity_packets);
  map_stage_ = std::make_unique<StageWorker<MapPacket>>(
      "mapping", [this](MapPacket& p) { handleMap(p); }, t, cap);
  loop_stage_ = std::make_unique<StageWorker<KeyframePacket>>(
      "loop closing", [this](KeyframePacket& p) { handleKeyframe(p); }, t, cap);
  odometry_stage_ = std::make_unique<StageWorker<OdometryInput>>(
      "odometry", [this](OdometryInput& in) { handleMeasurement(in); }, t, cap);
  if (t && cfg.pipeline.images_prepared_ahead > 0)
    preparer_ = std::make_unique<frontend::ImagePreparer>(cfg.frontend);
}

SlamSystem::~SlamSystem() = default;

void SlamSystem::feedImu(const ImuSample& imu) { odometry_stage_->submit({imu, std::nullopt}); }

void SlamSystem::feedWheel(const WheelOdometrySample& wheel) {
  // Without fusion the readings need not cross to the odometry thread at all.
  if (cfg_.estimator.wheel.enable) odometry_stage_->submit({wheel, std::nullopt});
}

void SlamSystem::feedRgbd(const RgbdFrame& frame) {
  OdometryInput in{options_.threaded ? ownedCopy(frame) : frame, std::nullopt};
  // The image is prepared here, on the feeding thread, while the odometry thread tracks the
  // images before it: at 30 Hz the odometry thread is the critical path. Waiting for the
  // odometry stage to track an older prepared image bounds the memory they hold.
  const bool prepare = preparer_ && frontend::ImagePreparer::accepts(frame);
  if (prepare) {
    if (prepared_handled_at_.size() >=
        static_cast<std::size_t>(cfg_.pipeline.images_prepared_ahead)) {
      odometry_stage_->waitHandled(prepared_handled_at_.front());
      prepared_handled_at_.pop_front();
    }
    in.prepared.emplace();
    {
      std::lock_guard<std::mutex> lock(spare_images_mutex_);
      if (!spare_images_.empty()) {
        *in.prepared = std::move(spare_images_.back());
        spare_images_.pop_back();
      }
    }
    preparer_->prepare(std::get<RgbdFrame>(in.measurement), *in.prepared);
    ++images_prepared_ahead_;
  }
  odometry_stage_->submit(std::move(in));
  if (prepare) prepared_handled_at_.push_back(odometry_stage_->submitted());
}

void SlamSystem::endOfStream() {
  if (ended_) return;
  ended_ = true;
  odometry_stage_->finish();
  spare_images_ = {};  // no image comes any more: their buffers are not kept for the end's work
  vio_.endOfStream();  // flushes the window: its keyframes go to loop closing
  loop_stage_->finish();
  if (geo_reloc_) {
    geo_reloc_->takeTrackingAtEnd(*closer_);
    geo_reloc_->finish();
  }
  if (closer_) closer_->finish();  // solves for loops accepted since the last solve
  computeFinalKeyframePoses();
  // The map follows the final poses (keyframes outside the graph included).
  MapPacket c;
  c.is_correction = true;
  for (std::size_t i = 0; i < keyframe_states_.size(); ++i)
    c.corrected_poses.emplace_back(keyframe_states_[i].id,
                                   final_keyframe_poses_[i] * cfg_.extrinsic.T_body_cam);
  if (closer_) map_stage_->submit(std::move(c));
  map_stage_->finish();
  mapper_->finish();
}

void SlamSystem::computeFinalKeyframePoses() {
  const std::size_t n = keyframe_states_.size();
  final_keyframe_poses_.assign(n, Eigen::Isometry3d::Identity());
  // Correction of the graph node nearest in time of the same segment (none: odometry).
  std::vector<long> node_of(n, -1);
  long last = -1;
  for (std::size_t i = 0; i < n; ++i) {
    if (last >= 0 && keyframe_states_[static_cast<std::size_t>(last)].state.segment !=
                         keyframe_states_[i].state.segment)
      last = -1;
    if (closer_ && i < in_loop_graph_.size() && in_loop_graph_[i]) last = static_cast<long>(i);
    node_of[i] = last;
  }
  long next = -1;
  for (std::size_t j = n; j-- > 0;) {
    if (next >= 0 && keyframe_states_[static_cast<std::size_t>(next)].state.segment !=
                         keyframe_states_[j].state.segment)
      next = -1;
    if (closer_ && j < in_loop_graph_.size() && in_loop_graph_[j]) next = static_cast<long>(j);
    if (node_of[j] < 0) node_of[j] = next;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Isometry3d& odom = keyframe_states_[i].state.T_world_body;
    if (node_of[i] < 0) {
      final_keyframe_poses_[i] = odom;
      continue;
    }
    const auto g = static_cast<std::size_t>(node_of[i]);
    const Eigen::Isometry3d T_g = closer_->pose(keyframe_states_[g].id);
    if (g == i) {
      final_keyframe_poses_[i] = T_g;
    } else {
      const Eigen::Isometry3d& odom_g = keyframe_states_[g].state.T_world_body;
      final_keyframe_poses_[i] =
          T_g.matrix() == odom_g.matrix() ? odom : T_g * odom_g.inverse() * odom;
    }
  }
}

bool SlamSystem::joinsLoopClosing(const KeyframePacket& p) {
  const Eigen::Isometry3d& T = p.state.T_world_body;
  const bool joins = [&] {
    if (p.state.segment != last_loop_segment_) return true;
    // The first keyframe after blind frames joins, so that the graph has the IMU-only stretch
    // as one edge of its own, trusted as little as the IMU alone deserves.
    if (bridged_since_loop_keyframe_ > 0.0) return true;
    // A part not yet placed in the origin's frame (a run in a loaded map, a segment after a
    // reset) queries with every keyframe: relocalising early matters more than the cost.
    if (closer_ && !closer_->connectedToOrigin(p.state.segment)) return true;
    const double d = (T.translation() - last_loop_keyframe_.translation()).norm();
    const double angle =
        Eigen::AngleAxisd(last_loop_keyframe_.rotation().transpose() * T.rotation()).angle();
    return d >= cfg_.loop.min_keyframe_distance_m ||
           angle >= cfg_.loop.min_keyframe_angle_deg * M_PI / 180.0;
  }();
  if (joins) {
    last_loop_keyframe_ = T;
    last_loop_segment_ = p.state.segment;
  }
  return joins;
}

void SlamSystem::handleMeasurement(OdometryInput& in) {
  if (auto* imu = std::get_if<ImuSample>(&in.measurement)) {
    vio_.feedImu(*imu);
  } else if (auto* wheel = std::get_if<WheelOdometrySample>(&in.measurement)) {
    vio_.feedWheel(*wheel);
  } else {
    const RgbdFrame& frame = std::get<RgbdFrame>(in.measurement);
    if (in.prepared) {
      vio_.feedRgbd(frame, *in.prepared);  // reads it during the call only
      std::lock_guard<std::mutex> lock(spare_images_mutex_);
      if (spare_images_.size() <= static_cast<std::size_t>(cfg_.pipeline.images_prepared_ahead))
        spare_images_.push_back(std::move(*in.prepared));
      in.prepared.reset();
    } else {
      vio_.feedRgbd(frame);
    }
    progress_frames_.store(vio_.framesReceived());
    progress_frame_t_.store(frame.t);
    progress_status_.store(static_cast<int>(vio_.status()));
  }
}

void SlamSystem::onFrame(const estimator::FrameEstimate& est, const RgbdFrame&) {
  if (est.reset) {
    ++frame_segment_;  // the estimator starts a new segment at every reset
    frame_segment_placed_ = false;
  }
  if (!est.has_pose) return;
  FrameRecord r;
  r.t_imu = est.t_imu;
  r.t_image = est.t_image;
  r.segment = frame_segment_;
  r.T_world_body_odom = est.T_world_body;
  r.blind = est.blind;
  bool in_origin = false;
  r.T_world_body_online = onlineDrift(frame_segment_, &in_origin) * est.T_world_body;
  r.online_in_map = options_.map && in_origin;
  if (in_origin) frame_segment_placed_ = true;
  frames_.push_back(r);
  if (options_.on_pose) options_.on_pose(frames_.back());
}

Eigen::Isometry3d SlamSystem::onlineDrift(int segment, bool* in_origin) {
  *in_origin = false;
  const std::size_t lag = static_cast<std::size_t>(cfg_.loop.offline_lag_keyframes);
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
  const auto& o = in_origin_after_keyframe_[entry - 1];
  *in_origin = segment < static_cast<int>(o.size()) && o[static_cast<std::size_t>(segment)];
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
  packet.id = id_offset_ + keyframe_states_.size();
  packet.state = kf;
  packet.state.segment += segment_offset_;
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

std::function<Eigen::Vector2d(const Eigen::Vector2d&)> SlamSystem::keypointsToStamp(
    const KeyframePacket& p) const {
  if (!(p.state.rolling_shutter_readout_s > 0.0)) return {};
  // Rolling shutter: the keypoints are moved to the stamp along the motion field of the
  // keyframe's state (doc/estimator.md), with the median depth of its tracked features.
  RollingShutter rs = cfg_.camera.rollingShutter();
  rs.readout_s = p.state.rolling_shutter_readout_s;
  rs.rows = loop_camera_.height;
  const CameraVelocity cam = cameraVelocity(
      cfg_.extrinsic.T_body_cam, p.state.T_world_body.rotation().transpose() * p.state.v_world,
      p.state.omega_body);
  std::vector<double> depths;
  for (const auto& f : p.features.features) depths.push_back(f.depth_m);
  const double typical = typicalDepth(std::move(depths));
  return [this, rs, cam, typical](const Eigen::Vector2d& uv) {
    return estimator::pixelAtReferenceTime(uv, loop_camera_, rs, cam.omega_cam, cam.v_cam, typical);
  };
}

void SlamSystem::handleKeyframe(KeyframePacket& p) {
  const Eigen::Isometry3d& T_bc = cfg_.extrinsic.T_body_cam;
  Eigen::Isometry3d T_world_body = p.state.T_world_body;
  bool solved = false;
  if (p.state.segment != last_loop_segment_) bridged_since_loop_keyframe_ = 0.0;
  bridged_since_loop_keyframe_ += p.state.bridged_s;
  const bool joins = cfg_.loop.enable && joinsLoopClosing(p);
  in_loop_graph_.push_back(joins ? 1 : 0);
  if (cfg_.loop.enable && !joins && closer_) {
    T_world_body = closer_->drift(p.state.segment) * p.state.T_world_body;
  } else if (joins) {
    if (!closer_) {
      loop_camera_ = vio_.cameraFor(p.frame);
      closer_ = std::make_unique<loop::LoopCloser>(cfg_.loop, loop_camera_, T_bc);
      extractor_ = std::make_unique<loop::LoopFeatureExtractor>(cfg_.loop.features, cfg_.frontend);
      if (options_.map) loadMap(loop_camera_);
    }
    loop::LoopKeyframe lk;
    lk.id = p.id;
    lk.segment = p.state.segment;
    lk.t = p.state.t_imu;
    lk.T_world_body_odom = p.state.T_world_body;
    lk.travelled_m = p.travelled_m;
    lk.bridged_s = bridged_since_loop_keyframe_;
    bridged_since_loop_keyframe_ = 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    lk.descriptors = extractor_->extract(p.frame, loop_camera_, keypointsToStamp(p));
    lk.depth_grid = extractor_->depthGrid(p.frame, loop_camera_);
    closer_->mutableStats().features_ms_total +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    solved = closer_->process(std::move(lk)).solved;
    if (geo_reloc_ && geo_reloc_->afterKeyframe(*closer_, loop_camera_)) solved = true;
    T_world_body = closer_->pose(p.id);
    const loop::LoopStats& ls = closer_->stats();
    progress_loops_.store(ls.accepted + ls.external - ls.rolled_back);
    if (options_.map)
      progress_map_state_.store(static_cast<int>(closer_->connectedToOrigin(p.state.segment)
                                                     ? MapState::kLocalised
                                                     : MapState::kNotLocalised));
  }

  MapPacket m;
  m.keyframe.id = p.id;
  m.keyframe.frame_index = p.state.frame_index;
  m.keyframe.t = p.frame.t;
  m.keyframe.T_world_cam = T_world_body * T_bc;
  for (const auto& f : p.features.features) {
    mapping::KeyframeFeature kfe;
    kfe.id = f.id;
    kfe.uv = f.uv.cast<float>();
    kfe.has_position = f.depth_m > 0.0;
    if (kfe.has_position)
      kfe.p_cam = (Eigen::Vector3d(f.xn.x(), f.xn.y(), 1.0) * f.depth_m).cast<float>();
    m.keyframe.features.push_back(kfe);
  }
  m.frame = std::move(p.frame);
  if (!(options_.map && options_.localize_only)) map_stage_->submit(std::move(m));
  if (solved) {
    // The map follows the corrected keyframes (paper 4.5).
    MapPacket c;
    c.is_correction = true;
    for (const auto& [id, T] : closer_->correctedPoses())
      c.corrected_poses.emplace_back(id, T * T_bc);
    map_stage_->submit(std::move(c));
  }
  std::vector<Eigen::Isometry3d> drift(static_cast<std::size_t>(p.state.segment) + 1,
                                       Eigen::Isometry3d::Identity());
  std::vector<char> in_origin(drift.size(), 0);
  for (std::size_t s = 0; s < drift.size(); ++s) {
    if (closer_) drift[s] = closer_->drift(static_cast<int>(s));
    in_origin[s] = segmentInOrigin(static_cast<int>(s)) ? 1 : 0;
  }
  std::lock_guard<std::mutex> lock(drift_mutex_);
  drift_after_keyframe_.push_back(std::move(drift));
  in_origin_after_keyframe_.push_back(std::move(in_origin));
}

void SlamSystem::handleMap(MapPacket& p) {
  if (p.is_correction) {
    mapper_->correct(p.corrected_poses);
  } else {
    mapper_->addKeyframe(std::move(p.keyframe), p.frame);
  }
  if (options_.on_map_update) options_.on_map_update(*mapper_, p.is_correction);
}

SlamProgress SlamSystem::progress() const {
  SlamProgress s;
  s.frames = progress_frames_.load();
  s.last_frame_t = progress_frame_t_.load();
  s.keyframes = progress_keyframes_.load();
  s.loops_accepted = progress_loops_.load();
  s.status = static_cast<estimator::EstimatorStatus>(progress_status_.load());
  s.map_state = mapState();
  if (geo_reloc_) {
    const GeoRelocReport r = geo_reloc_->report();
    if (r.results > 0) {
      s.geo_outcome = r.last_outcome;
      s.geo_places = r.last_places;
    }
  }
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
    if (!hasMap() || r.online_in_map)
      t.push_back(StampedPose::fromIsometry(r.t_imu, r.T_world_body_online));
  return t;
}

const char* toString(MapState s) {
  switch (s) {
    case MapState::kNoMap:
      return "no map";
    case MapState::kNotLocalised:
      return "not localised";
    case MapState::kLocalised:
      return "localised";
  }
  return "?";
}

MapState SlamSystem::mapState() const { return static_cast<MapState>(progress_map_state_.load()); }

bool SlamSystem::segmentInOrigin(int segment) const {
  if (!closer_) return !hasMap() && segment == 0;
  return closer_->connectedToOrigin(segment);
}

double SlamSystem::firstRelocalisationTime() const {
  if (!hasMap() || !closer_) return -1.0;
  for (const loop::JoinRecord& j : closer_->joins())
    if (j.to_segment == 0) return j.t_query;
  return -1.0;
}

double SlamSystem::firstOnlinePoseInMapTime() const {
  for (const FrameRecord& r : frames_)
    if (r.online_in_map) return r.t_imu;
  return -1.0;
}

void SlamSystem::loadMap(const PinholeCamera& camera) {
  // The stream's camera may differ from the configuration's (checked before the run).
  map::checkCompatible(options_.map->manifest, camera, cfg_.extrinsic.T_body_cam,
                       loop::kLoopDescriptorType, "the loaded map");
  closer_->loadMap(options_.map->places);
}

map::MapView SlamSystem::mapView(std::size_t* dropped_keyframes) const {
  if (!closer_)
    throw std::logic_error(
        "no map to save: loop closure did not run (a map needs its place "
        "keyframes)");
  map::MapView out;
  map::MapManifest& m = out.manifest;
  m.camera = loop_camera_;
  m.T_body_cam = cfg_.extrinsic.T_body_cam;
  m.descriptor_type = loop::kLoopDescriptorType;
  m.descriptor_bytes = cfg_.loop.place.index.descriptor_bytes;
  m.next_keyframe_id = id_offset_ + keyframe_states_.size();
  m.sessions = (hasMap() ? options_.map->manifest.sessions : 0) + 1;
  const auto& pi = cfg_.loop.place.index;
  m.index_parameters = "place_index_tables = " + std::to_string(pi.tables) +
                       "\nplace_index_key_bits = " + std::to_string(pi.key_bits) +
                       "\nplace_index_max_key_keyframes = " + std::to_string(pi.max_key_keyframes) +
                       "\nplace_index_seed = " + std::to_string(pi.seed) + "\n";

  // Keyframes of segments joined to the origin, at their corrected poses.
  for (const loop::LoopKeyframe& k : closer_->keyframes()) {
    const bool keep = k.segment == 0 || closer_->connectedToOrigin(k.segment);
    if (!keep) continue;
    out.places.push_back({&k, closer_->pose(k.id)});
  }
  m.next_segment = 1;
  for (const map::MapView::Place& p : out.places)
    m.next_segment = std::max(m.next_segment, p.keyframe->segment + 1);
  std::vector<std::uint64_t> saved_ids;  // increasing: places are in id order
  for (const map::MapView::Place& p : out.places) saved_ids.push_back(p.keyframe->id);
  auto isSaved = [&](std::uint64_t id) {
    return std::binary_search(saved_ids.begin(), saved_ids.end(), id);
  };
  if (hasMap())
    for (const map::MapLoopEdge& e : options_.map->loops) out.loops.push_back(e);
  for (const loop::LoopRecord& r : closer_->loops()) {
    if (!isSaved(r.constraint.from_id) || !isSaved(r.constraint.to_id)) continue;
    map::MapLoopEdge e;
    e.from_id = r.constraint.from_id;
    e.to_id = r.constraint.to_id;
    e.T_from_to = r.constraint.T_from_to;
    e.active = !r.rolled_back;
    out.loops.push_back(e);
  }

  std::size_t dropped = 0;
  const mapping::KeyframeStore& store = mapper_->store();
  for (std::size_t slot = 0; slot < store.size(); ++slot) {
    const mapping::Keyframe& k = store.at(slot);
    if (k.id >= id_offset_) {
      const std::size_t run_slot = static_cast<std::size_t>(k.id - id_offset_);
      if (run_slot < keyframe_states_.size() &&
          !segmentInOrigin(keyframe_states_[run_slot].state.segment)) {
        ++dropped;
        continue;
      }
    }
    out.keyframes.push_back(&k);
  }
  if (dropped_keyframes) *dropped_keyframes = dropped;
  return out;
}

void SlamSystem::bridgedCorrection(const FrameRecord& r, std::size_t k,
                                   Eigen::Isometry3d* D) const {
  // A blind frame's odometry pose is the IMU's propagation from the keyframe before the blind
  // stretch (k); its error grows until the first frame that sees again, whose pose as output
  // then (a record) still continued that propagation. Its final pose fixes the error at that
  // end, so the correction goes from keyframe k's to that one's along the square of the time
  // (an acceleration error integrated twice), instead of being one keyframe's for every frame.
  const std::size_t nk = std::min(keyframe_states_.size(), final_keyframe_poses_.size());
  if (k + 1 >= nk) return;
  const estimator::KeyframeState& a = keyframe_states_[k].state;
  const estimator::KeyframeState& b = keyframe_states_[k + 1].state;
  if (a.segment != r.segment || b.segment != r.segment || !(b.bridged_s > 0.0) ||
      !(a.t_imu <= r.t_imu && r.t_imu < b.t_imu))
    return;
  const auto it = std::lower_bound(frames_.begin(), frames_.end(), b.t_imu,
                                   [](const FrameRecord& f, double t) { return f.t_imu < t; });
  if (it == frames_.end() || it->t_imu != b.t_imu || it->segment != r.segment) return;
  const Eigen::Isometry3d D0 = final_keyframe_poses_[k] * a.T_world_body.inverse();
  const Eigen::Isometry3d D1 = final_keyframe_poses_[k + 1] * it->T_world_body_odom.inverse();
  const double tau = (r.t_imu - a.t_imu) / (b.t_imu - a.t_imu);
  const double w = tau * tau;
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(D0.linear())
                     .slerp(w, Eigen::Quaterniond(D1.linear()))
                     .normalized()
                     .toRotationMatrix();
  out.translation() = (1.0 - w) * D0.translation() + w * D1.translation();
  *D = out;
}

map::MapData SlamSystem::mapToSave(std::size_t* dropped_keyframes) const {
  return mapView(dropped_keyframes).copy();
}

Trajectory SlamSystem::finalTrajectory() const {
  // Correction of each keyframe: final pose * odometry pose^-1; a frame takes the correction of
  // the keyframe of its segment nearest in time (none: its segment has no keyframe, odometry).
  Trajectory t;
  t.reserve(frames_.size());
  std::size_t k = 0;
  const std::size_t nk = keyframe_states_.size();
  // A segment that ended in a reset ends with the frames the estimator went blind on: IMU-only
  // dead reckoning it gave up on (on the wheeled circle its error grows to 4 cm in the blind
  // second). The best estimate leaves them out: the gap starts where vision stopped. Frames of
  // a blindness the odometry bridged (no reset) stay.
  std::map<int, std::size_t> sight_end;  // per segment: index after its last frame with sight
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    auto& end = sight_end[frames_[i].segment];  // 0 for a segment not seen yet
    if (!frames_[i].blind) end = i + 1;
  }
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const FrameRecord& r = frames_[i];
    if (hasMap() && !segmentInOrigin(r.segment)) continue;  // never placed in the map
    if (r.segment < frame_segment_ && i >= sight_end[r.segment]) continue;  // blind before a reset
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
    if (best < nk && best < final_keyframe_poses_.size()) {
      const Eigen::Isometry3d& T_final = final_keyframe_poses_[best];
      const Eigen::Isometry3d& T_odom = keyframe_states_[best].state.T_world_body;
      // Exactly the odometry where the keyframe was not corrected (no loop in its segment).
      if (T_final.matrix() != T_odom.matrix()) D = T_final * T_odom.inverse();
    }
    if (r.blind) bridgedCorrection(r, k, &D);
    t.push_back(StampedPose::fromIsometry(r.t_imu, D * r.T_world_body_odom));
  }
  return t;
}

Trajectory SlamSystem::toCameraFrame(const Trajectory& body) const {
  // Camera poses carry the image stamps (camera clock). `body` may leave frames out (blind frames
  // before a reset, segments never placed in a map): each pose finds its frame by its IMU-clock
  // stamp, walking both in order.
  Trajectory t;
  t.reserve(body.size());
  std::size_t j = 0;
  for (std::size_t i = 0; i < body.size(); ++i) {
    while (j < frames_.size() && frames_[j].t_imu < body[i].t) ++j;
    const double stamp =
        j < frames_.size() && frames_[j].t_imu == body[i].t ? frames_[j].t_image : body[i].t;
    t.push_back(StampedPose::fromIsometry(stamp, body[i].isometry() * cfg_.extrinsic.T_body_cam));
  }
  return t;
}

}  // namespace rgbdi::system
