// The odometry as one push-based consumer of the measurement stream: front end + estimator.
// Frames are tracked as they arrive and queued until the IMU has reached their time, so the same
// object serves rawlogs, the in-process simulator and live sensors.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/estimator/sliding_window_estimator.h"
#include "rgbdi/frontend/feature_tracker.h"
#include "rgbdi/imu/imu_buffer.h"
#include "rgbdi/system/system_config.h"

namespace rgbdi::system {

struct VioTimings {
  double tracking_ms = 0.0;  ///< front end (KLT, detection, depth sampling), summed
  double preintegration_ms = 0.0;
  double optimisation_ms = 0.0;
  double marginalisation_ms = 0.0;
  int frames_tracked = 0;
  int frames_estimated = 0;
};

class VioSystem : public MeasurementSink {
 public:
  /// use_depth = false runs the monocular baseline: depth is ignored everywhere.
  VioSystem(const SystemConfig& cfg, bool use_depth);
  ~VioSystem() override;

  void feedImu(const ImuSample& imu) override;
  /// Wheel odometry for the estimator (used when [wheel] enable, doc/wheels.md).
  void feedWheel(const WheelOdometrySample& wheel) override;
  void feedRgbd(const RgbdFrame& frame) override;
  /// The same with the frame's image prepared ahead (frontend::ImagePreparer with this system's
  /// [frontend] options, e.g. on the feeding thread). Same result as without it.
  void feedRgbd(const RgbdFrame& frame, const frontend::PreparedImage& prepared);
  void endOfStream() override;

  /// Called for every processed frame (after the estimator ran on it).
  void setFrameCallback(std::function<void(const estimator::FrameEstimate&, const RgbdFrame&)> cb) {
    frame_cb_ = std::move(cb);
  }

  /// Called for every keyframe whose pose is final for the odometry (it left the window), and
  /// for the keyframes still in the window at the end of the stream, with the source frame.
  using KeyframeCallback = std::function<void(const estimator::KeyframeState&, const RgbdFrame&,
                                              const frontend::FeatureFrame&)>;
  void setKeyframeCallback(KeyframeCallback cb) { keyframe_cb_ = std::move(cb); }
  /// While `wanted(segment)` holds for the window's segment, the keyframe callback also gets the
  /// window keyframes that can no longer be dropped (all but the two newest slots) as soon as
  /// they are there, with the window's current pose, instead of when they leave the window. A
  /// part of the run not yet placed in a map relocalises from what it sees now, not a window
  /// later. Such a keyframe is handed out again when it leaves: the receiver skips keyframes
  /// it has (by time).
  void setEarlyKeyframes(std::function<bool(int segment)> wanted) {
    early_wanted_ = std::move(wanted);
  }
  /// All keyframes handed out so far (oldest first).
  const std::vector<estimator::KeyframeState>& keyframes() const { return keyframes_; }

  /// Causal trajectory: one pose per image processed after initialisation (body frame, IMU time).
  const Trajectory& trajectoryBody() const { return traj_body_; }
  /// The same poses in the colour-camera frame, stamped with the image stamps (camera clock).
  const Trajectory& trajectoryCamera() const { return traj_cam_; }
  const estimator::EstimatorStats& estimatorStats() const { return estimator_->stats(); }
  estimator::EstimatorStatus status() const { return estimator_->status(); }
  const VioTimings& timings() const { return timings_; }
  std::size_t framesReceived() const { return frames_received_; }
  std::size_t framesDropped() const { return frames_dropped_; }
  const Eigen::Isometry3d& T_body_cam() const { return cfg_.extrinsic.T_body_cam; }
  estimator::SlidingWindowEstimator& estimator() { return *estimator_; }
  double timeOffset() const { return estimator_->timeOffset(); }
  /// [s] the rolling-shutter readout: configured, or estimated ([estimator]
  /// estimate_rolling_shutter_readout).
  double rollingShutterReadout() const { return estimator_->rollingShutterReadout(); }
  /// With the readout estimated: (image stamp [s], estimate [s]) about once a second of stream.
  const std::vector<std::pair<double, double>>& readoutHistory() const { return readout_history_; }
  /// The colour camera used for `frame` ([camera] intrinsics_source: config or stream).
  PinholeCamera cameraFor(const RgbdFrame& frame) const;

 private:
  void track(const RgbdFrame& frame, const frontend::PreparedImage* prepared);
  struct Pending {
    frontend::FeatureFrame features;
    RgbdFrame frame;
  };
  void processReady(bool flush);
  /// The camera at t1 in the camera frame at t0 (camera stamps; the estimator's time offset and
  /// gyro bias applied): the gyroscope's rotation, and with klt_predict_translation the
  /// translation dead-reckoned from the estimate of the image at t0 when it has one.
  frontend::CameraMotion cameraMotion(double t0, double t1) const;
  void emitKeyframes(std::vector<estimator::KeyframeState> kfs);
  void emitEarlyKeyframes();
  const Pending* recentFrame(std::uint64_t frame_index) const;

  SystemConfig cfg_;
  bool use_depth_;
  std::unique_ptr<frontend::FeatureTracker> tracker_;
  std::unique_ptr<estimator::SlidingWindowEstimator> estimator_;
  std::deque<Pending> pending_;
  /// IMU samples since the last tracked image, for the front end's rotation prediction.
  imu::ImuBuffer gyro_history_;
  double last_tracked_t_ = 0.0;
  bool has_tracked_ = false;
  /// The newest frame's estimate (the prediction's velocity when it is the last tracked image's).
  std::optional<estimator::FrameEstimate> newest_estimate_;
  Trajectory traj_body_, traj_cam_;
  VioTimings timings_;
  std::size_t frames_received_ = 0, frames_dropped_ = 0;
  std::vector<std::pair<double, double>> readout_history_;
  std::function<void(const estimator::FrameEstimate&, const RgbdFrame&)> frame_cb_;
  KeyframeCallback keyframe_cb_;
  std::function<bool(int)> early_wanted_;
  double last_early_t_ = -1e300;
  std::vector<estimator::KeyframeState> keyframes_;
  /// Recent frames by index, so a keyframe leaving the window can be handed out with its images
  /// (bounded: the window spans at most this many frames).
  std::deque<Pending> recent_frames_;
};

}  // namespace rgbdi::system
