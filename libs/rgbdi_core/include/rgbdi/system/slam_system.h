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
#pragma once

#include <mrpt/obs/CObservation.h>

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/common/stage_worker.h"
#include "rgbdi/io/measurement_source.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/loop/loop_features.h"
#include "rgbdi/mapping/mapper.h"
#include "rgbdi/system/keyframe_packet.h"
#include "rgbdi/system/system_config.h"
#include "rgbdi/system/vio_system.h"

namespace rgbdi::system {

struct SlamSystemOptions {
  bool use_depth = true;  ///< false: monocular-inertial baseline (depth ignored everywhere)
  bool threaded = true;   ///< stages on their own threads (false: all inline, same result)
  bool live = false;      ///< live input: drift corrections taken when ready (wall time)
  bool keep_observations = false;   ///< keep each keyframe's MRPT observation (keyframes.simplemap)
  std::size_t queue_capacity = 64;  ///< [packets] bound of each stage queue
};

/// One processed image as the outputs need it.
struct FrameRecord {
  double t_imu = 0.0;    ///< [s] state time (IMU clock)
  double t_image = 0.0;  ///< [s] image stamp
  int segment = 0;       ///< odometry segment (increases at every reset)
  Eigen::Isometry3d T_world_body_odom = Eigen::Isometry3d::Identity();  ///< odometry alone
  Eigen::Isometry3d T_world_body_online =
      Eigen::Isometry3d::Identity();  ///< with the drift known then
};

/// A snapshot for progress lines (safe to take from any thread while the system runs).
struct SlamProgress {
  std::size_t frames = 0;
  std::size_t keyframes = 0;
  std::size_t loops_accepted = 0;
  estimator::EstimatorStatus status = estimator::EstimatorStatus::kInitializing;
};

class SlamSystem : public MeasurementSink {
 public:
  SlamSystem(const SystemConfig& cfg, const SlamSystemOptions& options);
  ~SlamSystem() override;

  void feedImu(const ImuSample& imu) override;
  void feedRgbd(const RgbdFrame& frame) override;
  /// Flushes the odometry window, lets every stage finish (final pose-graph solve, map
  /// correction, occupancy rebuild) and joins the threads. Rethrows a stage's failure.
  void endOfStream() override;

  SlamProgress progress() const;

  // --- results (complete after endOfStream) ---------------------------------------------------
  const std::vector<FrameRecord>& frames() const { return frames_; }
  /// Keyframes as the odometry handed them out (body poses, segments), in id order.
  const std::vector<KeyframePacket>& keyframeStates() const { return keyframe_states_; }
  const mapping::Mapper& mapper() const { return *mapper_; }
  /// nullptr when loop closure is off ([loop] enable = false) or no keyframe was made.
  const loop::LoopCloser* loopCloser() const { return closer_.get(); }
  /// The same, writable, for test hooks (LoopCloser::addExternalLoop). The loop-closing stage
  /// owns it: use it only between feeds of a sequential run (SlamSystemOptions::threaded =
  /// false) or after endOfStream. nullptr before the first keyframe.
  loop::LoopCloser* mutableLoopCloser() { return closer_.get(); }
  const VioSystem& odometry() const { return vio_; }
  /// Final body pose of keyframe `slot` (loop-corrected when loops closed).
  Eigen::Isometry3d keyframePose(std::size_t slot) const;
  /// Best estimate of every processed frame after the last solve: each frame carried by the
  /// correction of its keyframe (same segment, nearest in time).
  Trajectory finalTrajectory() const;
  Trajectory odometryTrajectory() const;
  Trajectory onlineTrajectory() const;
  /// The same three in the colour camera frame, stamped with the image stamps.
  Trajectory toCameraFrame(const Trajectory& body) const;
  /// MRPT observation of each keyframe, by slot (only with keep_observations).
  const std::vector<mrpt::obs::CObservation::Ptr>& observations() const { return observations_; }
  const Eigen::Isometry3d& T_body_cam() const { return cfg_.extrinsic.T_body_cam; }
  const SystemConfig& config() const { return cfg_; }
  std::size_t mapQueueHighWater() const { return map_stage_->queueHighWater(); }

 private:
  void handleMeasurement(io::Measurement& m);
  void onFrame(const estimator::FrameEstimate& est, const RgbdFrame& frame);
  void onKeyframe(const estimator::KeyframeState& kf, const RgbdFrame& frame,
                  const frontend::FeatureFrame& features);
  void handleKeyframe(KeyframePacket& p);
  void handleMap(MapPacket& p);
  /// Drift of `segment` to apply to the online pose now (see the file comment).
  Eigen::Isometry3d onlineDrift(int segment);

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
  /// Whether keyframe `p` joins loop closing (distance/angle from the last one that joined).
  bool joinsLoopClosing(const KeyframePacket& p);
  /// Final body poses of every keyframe once loop closing has finished.
  void computeFinalKeyframePoses();

  // Odometry-thread state.
  std::vector<FrameRecord> frames_;
  std::vector<KeyframePacket> keyframe_states_;  ///< without images (kept for the outputs)
  std::vector<mrpt::obs::CObservation::Ptr> observations_;
  int frame_segment_ = 0;
  double travelled_m_ = 0.0;
  double last_keyframe_t_ = -1e300;
  Eigen::Vector3d last_keyframe_p_ = Eigen::Vector3d::Zero();
  int last_keyframe_segment_ = -1;

  // Drift corrections published by the loop stage: entry k = drift of every segment after
  // keyframe k was handled (index = segment; segments not yet seen are identity).
  mutable std::mutex drift_mutex_;
  std::vector<std::vector<Eigen::Isometry3d>> drift_after_keyframe_;
  std::vector<Eigen::Isometry3d> final_keyframe_poses_;  ///< T_world_body by slot, at the end

  std::atomic<std::size_t> progress_frames_{0}, progress_keyframes_{0}, progress_loops_{0};
  std::atomic<int> progress_status_{0};

  // Declared last: destroyed (threads joined) before the state above.
  std::unique_ptr<StageWorker<MapPacket>> map_stage_;
  std::unique_ptr<StageWorker<KeyframePacket>> loop_stage_;
  std::unique_ptr<StageWorker<io::Measurement>> odometry_stage_;
  bool ended_ = false;
};

}  // namespace rgbdi::system
