// The SLAM system as one object: odometry (front end + sliding-window estimator), loop closing
// and mapping, each stage on its own thread behind a bounded queue, fed through MeasurementSink
// by any source (rawlog, simulator, live sensors). Sequential mode runs the same stages inline
// on the caller's thread and gives byte-identical results: stages hand packets on in order, and
// the one result that flows back upstream (the drift correction the odometry applies to its
// online poses) is taken at a defined point, after keyframe k - lag has been handled by loop
// closing, never "whatever is ready" (that is live mode only).
//
//   feedImu/feedRgbd -> [queue] odometry -> keyframe packets -> [queue] loop closing
//                    -> map packets (keyframes, corrections) -> [queue] mapping
//
// With a loaded map (SlamSystemOptions::map) the run starts "not localised": the odometry runs
// in its own frame while its keyframes query the map; the first relocalisation (stricter than
// a loop, loop_closer.h) moves the run into the map's frame, earlier poses included. The map is
// segment 0 of the pose graph and never moves; the run's segments are 1, 2, ... and its keyframe
// ids continue the map's. In mapping mode the run's keyframes extend the map; with
// localize_only the map stays as loaded.
#pragma once

#include <mrpt/obs/CObservation.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/common/stage_worker.h"
#include "rgbdi/frontend/prepared_image.h"
#include "rgbdi/io/measurement_source.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/loop/loop_features.h"
#include "rgbdi/map/map_data.h"
#include "rgbdi/mapping/mapper.h"
#include "rgbdi/system/geo_reloc_stage.h"
#include "rgbdi/system/keyframe_packet.h"
#include "rgbdi/system/system_config.h"
#include "rgbdi/system/vio_system.h"

namespace rgbdi::system {

struct FrameRecord;

struct SlamSystemOptions {
  bool use_depth = true;  ///< false: monocular-inertial baseline (depth ignored everywhere)
  bool threaded = true;   ///< stages on their own threads (false: all inline, same result)
  bool live = false;      ///< live input: drift corrections taken when ready (wall time)
  bool keep_observations = false;  ///< keep each keyframe's MRPT observation (keyframes.simplemap)
  /// A saved map to start in (nullptr: a new map). Needs loop closure ([loop] enable).
  std::shared_ptr<const map::MapData> map;
  bool localize_only = false;  ///< with a map: the map stays as loaded (it does not grow)
  /// Called on the odometry thread for every frame pose as it is produced (live latency
  /// figures); must be quick and thread-safe towards its owner.
  std::function<void(const FrameRecord&)> on_pose;
  /// Called on the mapping thread after the mapper took a keyframe (false) or a loop correction
  /// (true), with the mapper (live navigation maps: NavMapRefresher).
  std::function<void(const mapping::Mapper&, bool correction)> on_map_update;
};

/// One processed image as the outputs need it.
struct FrameRecord {
  double t_imu = 0.0;    ///< [s] state time (IMU clock)
  double t_image = 0.0;  ///< [s] image stamp
  int segment = 0;       ///< odometry segment (increases at every reset)
  Eigen::Isometry3d T_world_body_odom = Eigen::Isometry3d::Identity();  ///< odometry alone
  Eigen::Isometry3d T_world_body_online =
      Eigen::Isometry3d::Identity();  ///< with the drift known then
  /// With a map: the online pose is in the map's frame (the segment was relocalised then).
  bool online_in_map = false;
  bool blind = false;  ///< too few features: an IMU-only pose (FrameEstimate::blind)
};

/// Map state of a run (SlamProgress, summary).
enum class MapState { kNoMap, kNotLocalised, kLocalised };
const char* toString(MapState s);

/// A snapshot for progress lines (safe to take from any thread while the system runs).
struct SlamProgress {
  std::size_t frames = 0;  ///< frames the odometry has finished
  /// [s] stamp of the last frame the odometry finished (NaN: none yet). The reader runs ahead of
  /// the odometry behind bounded queues: this, not the reader's position, is the run's progress.
  double last_frame_t = std::numeric_limits<double>::quiet_NaN();
  std::size_t keyframes = 0;
  std::size_t loops_accepted = 0;
  estimator::EstimatorStatus status = estimator::EstimatorStatus::kInitializing;
  MapState map_state = MapState::kNoMap;
  /// Geometric relocalisation while not localised: the latest search's outcome ("ambiguous",
  /// "fit", ...; empty: none yet or no such search) and how many distinct places it saw.
  std::string geo_outcome;
  int geo_places = 0;
};

class SlamSystem : public MeasurementSink {
 public:
  SlamSystem(const SystemConfig& cfg, const SlamSystemOptions& options);
  ~SlamSystem() override;

  void feedImu(const ImuSample& imu) override;
  void feedWheel(const WheelOdometrySample& wheel) override;
  void feedRgbd(const RgbdFrame& frame) override;
  /// Flushes the odometry window, lets every stage finish (final pose-graph solve, map
  /// correction, occupancy rebuild) and joins the threads. Rethrows a stage's failure.
  void endOfStream() override;

  SlamProgress progress() const;

  // --- results (complete after endOfStream) ---------------------------------------------------
  const std::deque<FrameRecord>& frames() const { return frames_; }
  /// Keyframes as the odometry handed them out (body poses, segments), in id order.
  const std::deque<KeyframePacket>& keyframeStates() const { return keyframe_states_; }
  const mapping::Mapper& mapper() const { return *mapper_; }
  /// nullptr when loop closure is off ([loop] enable = false) or no keyframe was made.
  const loop::LoopCloser* loopCloser() const { return closer_.get(); }
  /// The same, writable, for test hooks (LoopCloser::addExternalLoop). The loop-closing stage
  /// owns it: use it only between feeds of a sequential run (SlamSystemOptions::threaded =
  /// false) or after endOfStream. nullptr before the first keyframe.
  loop::LoopCloser* mutableLoopCloser() { return closer_.get(); }
  const VioSystem& odometry() const { return vio_; }
  /// The loaded map (nullptr when the run started a new one).
  const map::MapData* loadedMap() const { return options_.map.get(); }
  /// Final body pose of keyframe `slot` (loop-corrected when loops closed).
  Eigen::Isometry3d keyframePose(std::size_t slot) const;
  /// Best estimate of every processed frame after the last solve: each frame carried by the
  /// correction of its keyframe (same segment, nearest in time). With a map: only the frames
  /// of segments relocalised in it (in the map's frame).
  Trajectory finalTrajectory() const;
  Trajectory odometryTrajectory() const;
  /// Causal poses; with a map only those taken once their segment was relocalised.
  Trajectory onlineTrajectory() const;
  /// With a map: the run's state now (kNoMap otherwise).
  MapState mapState() const;
  bool hasMap() const { return options_.map != nullptr; }
  /// [s] stamp (IMU clock) of the keyframe whose match relocalised the run in the loaded map
  /// (the view that was recognised); < 0 when none.
  double firstRelocalisationTime() const;
  /// [s] stamp (IMU clock) of the first frame whose online pose was in the map's frame: when a
  /// robot running this had its pose in the map (the match above plus the time to find and
  /// confirm it); < 0 when none.
  double firstOnlinePoseInMapTime() const;
  /// Geometric relocalisation's account (nullptr without a map or with [relocalise] geometric
  /// off); report() is safe from any thread.
  const GeoRelocStage* geoReloc() const { return geo_reloc_.get(); }
  /// Frame segment -> joined to the origin (the loaded map, or the run's first segment).
  bool segmentInOrigin(int segment) const;
  /// The map this run leaves (after endOfStream): the loaded map (if any) plus the run's
  /// keyframes of segments joined to the origin, in the origin's frame; `dropped_keyframes`
  /// counts the run's keyframes left out (segments never joined). Throws std::logic_error when
  /// loop closure never ran (a map needs its place keyframes).
  map::MapData mapToSave(std::size_t* dropped_keyframes = nullptr) const;
  /// The same map by reference to this system's keyframes (what rgbdi-slam saves: no copy of
  /// the descriptors and keyframes); valid while the system lives and is not fed again.
  map::MapView mapView(std::size_t* dropped_keyframes = nullptr) const;
  /// Keyframe ids of this run start here (the loaded map's next id, else 0).
  std::uint64_t firstKeyframeId() const { return id_offset_; }
  /// The same three in the colour camera frame, stamped with the image stamps.
  Trajectory toCameraFrame(const Trajectory& body) const;
  /// MRPT observation of each keyframe, by slot (only with keep_observations).
  const std::vector<mrpt::obs::CObservation::Ptr>& observations() const { return observations_; }
  const Eigen::Isometry3d& T_body_cam() const { return cfg_.extrinsic.T_body_cam; }
  const SystemConfig& config() const { return cfg_; }
  const SlamSystemOptions& options() const { return options_; }
  std::size_t mapQueueHighWater() const { return map_stage_->queueHighWater(); }
  /// Images prepared for tracking on the feeding thread ([pipeline] images_prepared_ahead);
  /// read it from the feeding thread or after endOfStream().
  std::uint64_t imagesPreparedAhead() const { return images_prepared_ahead_; }

 private:
  /// A measurement for the odometry stage, with its image prepared when the feeding thread did.
  struct OdometryInput {
    io::Measurement measurement;
    std::optional<frontend::PreparedImage> prepared;
  };
  void handleMeasurement(OdometryInput& in);
  void onFrame(const estimator::FrameEstimate& est, const RgbdFrame& frame);
  void onKeyframe(const estimator::KeyframeState& kf, const RgbdFrame& frame,
                  const frontend::FeatureFrame& features);
  void handleKeyframe(KeyframePacket& p);
  /// Rolling shutter: maps a loop keypoint's pixel to its pixel at the keyframe's stamp; empty
  /// with a global shutter.
  std::function<Eigen::Vector2d(const Eigen::Vector2d&)> keypointsToStamp(
      const KeyframePacket& p) const;
  void handleMap(MapPacket& p);
  /// Drift of `segment` to apply to the online pose now (see the file comment); `in_origin`
  /// says whether the segment was joined to the origin then.
  Eigen::Isometry3d onlineDrift(int segment, bool* in_origin);
  /// The loaded map into the loop closer and the mapper (first keyframe: the camera is known).
  void loadMap(const PinholeCamera& camera);

  SystemConfig cfg_;
  SlamSystemOptions options_;
  VioSystem vio_;
  std::unique_ptr<mapping::Mapper> mapper_;
  // Loop-closing-thread state (created at the first keyframe: the camera may come from the stream).
  std::unique_ptr<loop::LoopCloser> closer_;
  std::unique_ptr<loop::LoopFeatureExtractor> extractor_;
  PinholeCamera loop_camera_;
  std::vector<char> in_loop_graph_;  ///< by keyframe slot: joined loop closing (a graph node)
  Eigen::Isometry3d last_loop_keyframe_ = Eigen::Isometry3d::Identity();
  int last_loop_segment_ = -1;
  /// [s] carried by the IMU alone since the newest keyframe in the loop graph (same segment)
  double bridged_since_loop_keyframe_ = 0.0;
  /// Whether keyframe `p` joins loop closing (distance/angle from the last one that joined).
  bool joinsLoopClosing(const KeyframePacket& p);
  /// Final body poses of every keyframe once loop closing has finished.
  /// The correction of a blind frame `r` of the final trajectory whose keyframe before it is k:
  /// unchanged unless keyframe k + 1 ends the IMU-only stretch r is in (see the definition).
  void bridgedCorrection(const FrameRecord& r, std::size_t k, Eigen::Isometry3d* D) const;
  void computeFinalKeyframePoses();

  // Odometry-thread state.
  // Deques: one record per image of a run of any length. A vector doubles its block and holds
  // both while it copies (heaptrack, 10-minute run: 18,001 frame records of 5.3 MB in a 9.7 MB
  // block, 14.5 MB while it grew).
  std::deque<FrameRecord> frames_;
  std::deque<KeyframePacket> keyframe_states_;  ///< without images (kept for the outputs)
  std::vector<mrpt::obs::CObservation::Ptr> observations_;
  int frame_segment_ = 0;
  /// Whether the odometry thread knows frame_segment_ to be placed in the origin's frame (from
  /// the drift entries it reads at defined points): until then keyframes go out early.
  bool frame_segment_placed_ = false;
  double travelled_m_ = 0.0;
  double last_keyframe_t_ = -1e300;
  Eigen::Vector3d last_keyframe_p_ = Eigen::Vector3d::Zero();
  int last_keyframe_segment_ = -1;

  // Drift corrections published by the loop stage: entry k = drift of every segment after
  // keyframe k was handled (index = segment; segments not yet seen are identity).
  mutable std::mutex drift_mutex_;
  std::vector<std::vector<Eigen::Isometry3d>> drift_after_keyframe_;
  std::vector<std::vector<char>> in_origin_after_keyframe_;  ///< same indexing: joined to origin
  std::vector<Eigen::Isometry3d> final_keyframe_poses_;      ///< T_world_body by slot, at the end

  std::atomic<std::size_t> progress_frames_{0}, progress_keyframes_{0}, progress_loops_{0};
  std::atomic<int> progress_status_{0};
  std::atomic<int> progress_map_state_{0};
  std::atomic<double> progress_frame_t_{std::numeric_limits<double>::quiet_NaN()};

  // Feeding thread only: the preparer (threaded with images_prepared_ahead > 0) and, for each
  // prepared image not known to be tracked, the odometry stage's packet count once it is handled.
  std::unique_ptr<frontend::ImagePreparer> preparer_;
  std::deque<std::uint64_t> prepared_handled_at_;
  std::uint64_t images_prepared_ahead_ = 0;
  // Prepared images whose tracking is done, handed back by the odometry thread for reuse: no
  // fresh 1.5 MB of buffers per image (page faults, and a fragmented heap on long runs).
  std::mutex spare_images_mutex_;
  std::vector<frontend::PreparedImage> spare_images_;

  std::uint64_t id_offset_ = 0;  ///< keyframe id = id_offset_ + slot
  int segment_offset_ = 0;       ///< frame/keyframe segment = estimator segment + this

  /// With a map: geometric relocalisation (its worker thread is fed by the loop stage).
  std::unique_ptr<GeoRelocStage> geo_reloc_;
  // Declared last: destroyed (threads joined) before the state above.
  std::unique_ptr<StageWorker<MapPacket>> map_stage_;
  std::unique_ptr<StageWorker<KeyframePacket>> loop_stage_;
  std::unique_ptr<StageWorker<OdometryInput>> odometry_stage_;
  bool ended_ = false;
};

}  // namespace rgbdi::system
