// Depth-aided sliding-window visual-inertial estimator (paper section 4.3, eq. 10).
//
// Push-based: feedImu() for every IMU sample, processFrame() for every tracked image (after the
// IMU has reached the image time). Each processed frame returns the state of that frame as
// estimated when it was the newest (causal output, as a robot would use it).
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::estimator {

enum class EstimatorStatus { kInitializing, kTracking, kLost };
const char* toString(EstimatorStatus s);

/// Per-frame output.
struct FrameEstimate {
  double t_imu = 0.0;    ///< state time on the IMU clock (= image stamp + time offset) [s]
  double t_image = 0.0;  ///< image stamp as received [s]
  bool has_pose = false;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_acc = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_gyr = Eigen::Vector3d::Zero();
  double time_offset_s = 0.0;
  double rolling_shutter_readout_s = 0.0;  ///< [s] configured or estimated readout
  EstimatorStatus status = EstimatorStatus::kInitializing;
  bool just_initialised = false;
  bool reset = false;  ///< a failure was detected and the estimator restarted
  /// While tracking: the frame had fewer than fail_min_features features (its pose is the IMU's
  /// propagation; if the blindness lasts past fail_max_blind_s the estimator resets).
  bool blind = false;
  int n_features_used = 0;
  int n_depth_verified = 0;
  double ms_optimisation = 0.0;
  double ms_marginalisation = 0.0;
  double ms_preintegration = 0.0;
};

/// A keyframe leaving the window (its pose is final for the odometry): for the mapper/pose graph.
struct KeyframeState {
  double t_imu = 0.0;
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  std::uint64_t frame_index = 0;
  /// Odometry segment: 0 until the first reset, then one more after each reset. Keyframes of
  /// different segments are not related by odometry (each restart has a frame of its own).
  int segment = 0;
  /// [s] of the interval since the previous keyframe carried by the IMU alone (blind frames:
  /// a blackout, a bare wall, motion blur), which the pose graph trusts less than tracking.
  double bridged_s = 0.0;
  /// Motion at the stamp and the rolling-shutter readout then (loop keypoints are moved to the
  /// stamp with them): velocity [m/s] in the world, rate [rad/s] (gyro minus bias) in the body
  /// frame, readout [s] (0 = global shutter).
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();
  double rolling_shutter_readout_s = 0.0;
};

struct EstimatorStats {
  int frames = 0;
  int resets = 0;
  int blind_resets = 0;  ///< of which: no features for longer than fail_max_blind_s
  int static_initialisations = 0;
  int moving_initialisations = 0;  ///< from motion (depth-aided PnP or visual SfM)
  int wheel_initialisations = 0;   ///< from the wheels and the IMU ([wheel] start_from_wheels)
  int visual_initialisations = 0;  ///< of which visual SfM (no depth)
  double first_pose_t_image = -1.0;
  /// [ms] thread CPU time of the stages, summed over all frames
  double sum_ms_optimisation = 0.0, sum_ms_marginalisation = 0.0, sum_ms_preintegration = 0.0;
  int optimisations = 0;                 ///< solver runs (window updates)
  int solver_iterations = 0;             ///< Ceres iterations summed over those runs
  int solver_iterations_capped = 0;      ///< runs that stopped at max_iterations
  int single_step_updates = 0;           ///< of the runs: limited to one step (non_keyframe_update)
  int solver_factorisation_retries = 0;  ///< damped systems that needed more damping
  /// Why the odometry waited for a pose: frames on which a start was tried and failed, by reason
  /// ("static start: ...", "moving start: ...": each such frame tries both that are enabled; "no
  /// IMU data up to the image" when it could try neither), over every start of the run (the
  /// first and those after resets). Ordered by the reason's text.
  std::map<std::string, int> init_waits;
  /// Wheel odometry ([wheel] enable): intervals between window frames that left the window with
  /// their wheel factor, and without one (no readings covering them: a stream gap); wheel
  /// factors summed over the solves; the learned scale factors (true = scale * reported).
  int wheel_intervals_used = 0, wheel_intervals_gap = 0, wheel_factors_solved = 0;
  /// Intervals left out because their factor disagreed with IMU and vision, by kind; factors
  /// left out of solves by the gate (summed over updates).
  int wheel_intervals_slip = 0, wheel_intervals_stuck = 0, wheel_intervals_lifted = 0;
  int wheel_factors_gated = 0;
  /// Ground-plane constraints of frames used and left out by their gate (summed over updates).
  int ground_plane_used = 0, ground_plane_gated = 0;
  /// Runs of consecutive left-out intervals of one kind ("slip", "stuck", "lifted"), IMU clock.
  struct WheelFaultEpisode {
    double t_start = 0.0, t_end = 0.0;  ///< [s]
    std::string kind;
  };
  std::vector<WheelFaultEpisode> wheel_fault_episodes;
  double wheel_scale_v = 1.0, wheel_scale_w = 1.0;
  /// [rad] the learnt correction about the wheel frame's z to the configured extrinsic; [s] the
  /// wheel time offset (the configured ones unless [wheel] estimate_extrinsic_yaw /
  /// estimate_time_offset).
  double wheel_extrinsic_yaw_rad = 0.0, wheel_time_offset_s = 0.0;
};

class SlidingWindowEstimator : public mrpt::system::COutputLogger {
 public:
  SlidingWindowEstimator(const EstimatorOptions& opt, const ImuOptions& imu,
                         const ExtrinsicOptions& ext);
  ~SlidingWindowEstimator();

  /// IMU samples in time order.
  void feedImu(const ImuSample& s);
  /// Wheel-odometry readings in time order (kept only when [wheel] enable).
  void feedWheel(const WheelOdometrySample& w);
  /// Latest IMU time received (frames must wait until this passes their time).
  double latestImuTime() const;
  /// Current time offset estimate: t_imu = t_image + timeOffset().
  double timeOffset() const;
  /// The colour images' row timing (CameraOptions::rollingShutter()); default global shutter:
  /// every observation is moved to its image's reference time along its image velocity.
  void setRollingShutter(const RollingShutter& rs);
  /// [s] current readout: the configured one, or its estimate with
  /// [estimator] estimate_rolling_shutter_readout.
  double rollingShutterReadout() const;
  /// Gyroscope bias of the newest window slot [rad/s] (zero before the first slot).
  Eigen::Vector3d gyroBias() const;
  /// Processes a tracked frame; `frame.t` is the image stamp. Requires IMU up to t + timeOffset().
  FrameEstimate processFrame(const frontend::FeatureFrame& frame);

  /// Keyframes that left the window since the last call (oldest first); at a reset the window's
  /// keyframes leave it too, with their states of the last successful update.
  std::vector<KeyframeState> takeFinishedKeyframes();
  /// States of the keyframes still in the window (for flushing at the end of a run).
  std::vector<KeyframeState> windowKeyframes() const;
  const EstimatorStats& stats() const { return stats_; }
  EstimatorStatus status() const { return status_; }

 private:
  /// The collaborators: the window and its problem, the starts (internal headers in
  /// src/estimator/, listed in doc/estimator.md "Source files").
  struct Parts;

  /// While initialising: tries the enabled starts on the frame at IMU-clock time `t`; true when
  /// the window holds a start (which is then solved).
  bool start(const frontend::FeatureFrame& frame, double t, FrameEstimate& out);
  bool tryStart(const frontend::FeatureFrame& frame, double t);
  /// While tracking: the frame joins the window, which is solved, checked and slid; false when
  /// `out` is already complete (blind frame or frame between updates: the IMU carries the pose;
  /// a reset).
  bool track(const frontend::FeatureFrame& frame, double t, FrameEstimate& out);
  /// The IMU propagation of the newest slot's state to IMU-clock time `t`.
  void propagateWithImu(double t, FrameEstimate& out);
  void addSlot(const frontend::FeatureFrame& frame, double t, bool predict_from_previous);
  /// Image velocities of slot `slot` from its state (time_offset_velocity = motion_field).
  void assignMotionFieldVelocities(std::size_t slot);
  /// Solves the window; `single_step`: the second-newest frame is no keyframe and leaves the
  /// window afterwards (one solver iteration when non_keyframe_update = single_step).
  void optimise(FrameEstimate* out, bool single_step);
  void marginaliseAndSlide(bool newest_but_one_is_keyframe, FrameEstimate* out);
  /// Counts `why` as the reason the start `path` ("static start: ", ...) failed on this frame.
  void countStartWait(const char* path, const char* why);
  /// [s] how far back the start from the wheels looks (its window and the readings' lag).
  double wheelStartHistory_s() const;
  void reset(bool keep_anchor);

  EstimatorOptions opt_;
  ImuOptions imu_opt_;
  std::unique_ptr<Parts> parts_;

  EstimatorStatus status_ = EstimatorStatus::kInitializing;
  // Anchor for re-initialisation after a failure: the trajectory continues from the last pose.
  bool have_anchor_ = false;
  Eigen::Vector3d anchor_p_ = Eigen::Vector3d::Zero();
  double anchor_yaw_ = 0.0;
  Eigen::Vector3d prev_newest_p_ = Eigen::Vector3d::Zero();
  double prev_newest_t_ = 0.0;
  double last_sighted_t_ = 0.0;  ///< [s] image stamp of the newest frame with fail_min_features
  bool bridging_ = false;        ///< blind frames since the newest slot (the IMU carries the pose)
  double last_preintegration_ms_ = 0.0;  ///< [ms] CPU time of the newest slot's pre-integration
  std::vector<KeyframeState> finished_keyframes_;
  /// States of the window's keyframes after the last successful update: handed out at a reset,
  /// so keyframes still in the window are not lost (the failed update's states are not used).
  std::vector<KeyframeState> last_good_window_;
  int segment_ = 0;
  EstimatorStats stats_;
};

}  // namespace rgbdi::estimator
