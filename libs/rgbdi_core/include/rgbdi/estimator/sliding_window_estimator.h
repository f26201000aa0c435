// Depth-aided sliding-window visual-inertial estimator (paper section 4.3, eq. 10).
//
// Push-based: feedImu() for every IMU sample, processFrame() for every tracked image (after the
// IMU has reached the image time). Each processed frame returns the state of that frame as
// estimated when it was the newest (causal output, as a robot would use it).
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/types.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/feature_manager.h"
#include "rgbdi/estimator/window_solver.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::imu {
class Preintegration;
class ImuBuffer;
}  // namespace rgbdi::imu

namespace rgbdi::estimator {

class MarginalizationInfo;
class StaticStart;

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
};

struct EstimatorStats {
  int frames = 0;
  int resets = 0;
  int blind_resets = 0;  ///< of which: no features for longer than fail_max_blind_s
  int static_initialisations = 0;
  int moving_initialisations = 0;  ///< from motion (depth-aided PnP or visual SfM)
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
};

class SlidingWindowEstimator : public mrpt::system::COutputLogger {
 public:
  SlidingWindowEstimator(const EstimatorOptions& opt, const ImuOptions& imu,
                         const ExtrinsicOptions& ext);
  ~SlidingWindowEstimator();

  /// IMU samples in time order.
  void feedImu(const ImuSample& s);
  /// Latest IMU time received (frames must wait until this passes their time).
  double latestImuTime() const;
  /// Current time offset estimate: t_imu = t_image + timeOffset().
  double timeOffset() const { return td_; }
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
  struct Slot;

  bool tryStaticInit(const frontend::FeatureFrame& frame, double t);
  bool tryMovingInit();
  bool tryVisualInit();
  /// Removes the second-newest slot, merging its IMU interval into the newest one's.
  void dropSecondNewestSlot();
  /// Sets the window's states from an initialisation solved in a reference frame (first camera).
  void adoptInitialisation(const std::vector<Eigen::Isometry3d>& T_ref_body,
                           const std::vector<Eigen::Vector3d>& v_ref, const Eigen::Vector3d& g_ref,
                           const Eigen::Vector3d& bg);
  void addSlot(const frontend::FeatureFrame& frame, double t, bool predict_from_previous);
  /// Solves the window; `single_step`: the second-newest frame is no keyframe and leaves the
  /// window afterwards (one solver iteration when non_keyframe_update = single_step).
  void optimise(FrameEstimate* out, bool single_step);
  void marginaliseAndSlide(bool newest_but_one_is_keyframe, FrameEstimate* out);
  bool failureDetected() const;
  std::string failureReason() const;
  /// Records `why` as the reason of the start being tried (counted in stats_.init_waits by
  /// processFrame) and returns false.
  bool initFail(const char* why);
  void reset(bool keep_anchor);
  SlotPoses slotPoses() const;
  double depthPriorSigma(const FeatureTrack& f) const;
  /// Replaces the image velocities of the observations in window slot `slot` by the motion field
  /// of that slot's state (see motion_field.h); no-op in "tracked" velocity mode.
  void assignMotionFieldVelocities(std::size_t slot);
  void rejectOutliers();
  std::vector<std::pair<std::uint64_t, TrackObservation>> toObservations(
      const frontend::FeatureFrame& frame) const;

  EstimatorOptions opt_;
  ImuOptions imu_opt_;
  Eigen::Isometry3d T_bc_;
  double td_;
  double td_config_;  ///< configured time offset: the prior mean
  double sqrt_info_;
  DepthCheckOptions depth_opt_;

  std::unique_ptr<imu::ImuBuffer> imu_;
  std::vector<Slot> window_;  ///< capacity window_size + 1, never reallocated
  FeatureManager features_;
  std::shared_ptr<MarginalizationInfo> prior_;
  double td_param_[1] = {0.0};
  std::vector<double> inv_depth_params_;  ///< the solved inverse depths during optimise()
  WindowSolver solver_;                   ///< optimise()'s solver (its buffers are reused)
  /// optimise()'s reprojection factors, reused from update to update (reset, not reallocated)
  std::vector<std::unique_ptr<ReprojectionFactor>> reprojection_factors_;
  std::vector<double*> residual_blocks_;  ///< optimise()'s work buffer
  // Prior on the first state's speed and biases from the initialisation (until marginalised).
  bool use_init_prior_ = false;
  Eigen::Matrix<double, 9, 1> init_prior_mean_ = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 9, 1> init_prior_sigma_ = Eigen::Matrix<double, 9, 1>::Ones();
  bool newest_but_one_keyframe_ = true;
  bool visual_init_mode_ = false;      ///< initialising from images alone (frames lack depth)
  const char* init_fail_reason_ = "";  ///< of the last initFail (a string literal)

  EstimatorStatus status_ = EstimatorStatus::kInitializing;
  // Anchor for re-initialisation after a failure: the trajectory continues from the last pose.
  bool have_anchor_ = false;
  Eigen::Vector3d anchor_p_ = Eigen::Vector3d::Zero();
  double anchor_yaw_ = 0.0;
  Eigen::Vector3d last_bg_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d prev_newest_p_ = Eigen::Vector3d::Zero();
  double prev_newest_t_ = 0.0;
  double last_sighted_t_ =
      0.0;                 ///< [s] image stamp of the newest frame with fail_min_features features
  bool bridging_ = false;  ///< blind frames since the newest slot (the IMU carries the pose)
  double last_preintegration_ms_ = 0.0;  ///< [ms] CPU time of the newest slot's pre-integration
  std::vector<KeyframeState> finished_keyframes_;
  /// States of the window's keyframes after the last successful update: handed out at a reset,
  /// so keyframes still in the window are not lost (the failed update's states are not used).
  std::vector<KeyframeState> last_good_window_;
  int segment_ = 0;
  /// Recent frames while initialising and the stillness test (src/estimator/static_start.h).
  std::unique_ptr<StaticStart> static_start_;
  EstimatorStats stats_;
};

}  // namespace rgbdi::estimator
