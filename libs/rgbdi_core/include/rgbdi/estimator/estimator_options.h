// Options of the sliding-window estimator and its initialisation ([estimator] section).
#pragma once

#include <string>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/estimator/wheel_options.h"

namespace rgbdi::estimator {

struct EstimatorOptions {
  int window_size = 10;                ///< [frames] keyframes in the sliding window
  double keyframe_parallax_px = 10.0;  ///< [px at focal 460] mean parallax making a keyframe
  int keyframe_min_tracked = 20;       ///< [count] fewer tracked features -> keyframe
  /// The keyframe parallax without the part the camera's rotation between the two frames
  /// explains (from their window poses): rotation alone moves every feature but adds no
  /// triangulation baseline, and at 15 Hz a hand-held camera's turning made most frames
  /// keyframes. false = raw parallax (VINS).
  bool keyframe_parallax_without_rotation = false;
  int max_iterations = 8;          ///< [count] solver iterations per update
  double max_solver_time_s = 0.0;  ///< [s] live-mode budget; 0 = unbounded (deterministic)
  /// [unitless] an update stops when an iteration lowers the cost by less than this fraction
  /// (Ceres' default function_tolerance is 1e-6), when the window holds depth-verified
  /// features. Iterations that gain less than 0.1 % moved no RGB-D trajectory by more than noise
  /// (doc/performance.md) and were half of the cost.
  double solver_function_tolerance = 1e-3;
  /// [unitless] the same without depth-verified features (monocular, --no-depth): the scale
  /// rests on the IMU alone there, and stopping at 1e-3 let it drift (handheld 30 Hz mono: ATE
  /// 0.050 -> 0.181 m and a reset).
  double solver_function_tolerance_no_depth = 1e-6;
  /// Update when the second-newest frame is not a keyframe (its measurements leave the window
  /// right after): "full" (up to max_iterations) or "single_step" (one solver iteration: the
  /// window is solved fully again with the next keyframe; without depth-verified features
  /// always "full"). Robot profiles: optimisation -17 to -33 %, ATE within 0.5 %
  /// (doc/performance.md).
  std::string non_keyframe_update = "single_step";
  double reprojection_sigma_px = 1.5;  ///< [px at focal 460]
  double cauchy_loss_sigma = 1.0;      ///< [unitless] Cauchy scale in units of reprojection sigma
  double depth_verify_tolerance_px = 10.0;  ///< [px at focal 460]
  double depth_verify_min_m = 0.1;          ///< [m]
  double depth_verify_max_m = 5.0;          ///< [m]
  /// How depth-verified features enter the optimisation: "constant" (paper: inverse depth held
  /// fixed) or "prior" (free inverse depth with a Gaussian prior from the verified mean, sigma
  /// from depth_noise_coeff and the number of agreeing observations).
  std::string verified_depth = "prior";
  double depth_noise_coeff = 0.004;            ///< [1/m] sensor depth sigma = coeff * z^2
  double init_depth_max_m = 10.0;              ///< [m]
  int init_min_correspondences = 20;           ///< [count]
  double init_min_parallax_px = 30.0;          ///< [px at focal 460]
  double init_static_max_gyro_rad_s = 0.02;    ///< [rad/s]
  double init_static_max_acc_std_m_s2 = 0.15;  ///< [m/s^2]
  double init_static_window_s = 0.2;           ///< [s] stillness is judged over this much data
  double init_static_max_acc_dev_m_s2 = 0.3;   ///< [m/s^2] | |mean acc| - g | allowed when still
  double init_static_max_motion_px = 1.0;      ///< [px at focal 460] mean feature motion when still
  int init_min_frames = 5;                     ///< [count] frames for a moving (PnP) initialisation
  double init_min_span_s = 0.15;               ///< [s] time spanned by those frames
  /// [m and m/s] RMS residual of the velocity/gravity alignment above which the IMU and the
  /// visual motion are judged inconsistent (clean data: < 0.002; an IMU shock: 0.01)
  double init_max_alignment_rms = 0.005;
  /// [s] image interval that init_max_alignment_rms is set for; with longer intervals between the
  /// images of the initialisation window (a slow camera, images dropped by an overloaded live run)
  /// the gate grows in proportion to the mean interval: the accelerometer bias, unknown at this
  /// point, makes the residual grow with the interval (0.006-0.010 with 0.3 s on clean data)
  double init_alignment_interval_s = 0.1;
  /// Start while still (gravity from the accelerometer); false waits for motion, as VINS-Mono does
  bool init_allow_static = true;
  /// [unitless] without depth: largest predicted relative error of the SfM scale to accept
  double init_max_scale_rel_sigma = 0.3;
  double init_acc_bias_sigma_m_s2 = 0.2;         ///< [m/s^2] prior std of the accelerometer bias
  double init_gyr_bias_sigma_rad_s = 0.01;       ///< [rad/s] prior std of the gyro bias
  double init_static_velocity_sigma_m_s = 0.02;  ///< [m/s] prior std of velocity at a static start
  double outlier_reprojection_px =
      3.0;  ///< [px at focal 460] mean reprojection error that rejects a feature
  double repropagate_acc_bias_m_s2 = 0.05;    ///< [m/s^2] re-integrate when ba moves this far
  double repropagate_gyr_bias_rad_s = 0.005;  ///< [rad/s] re-integrate when bg moves this far
  bool estimate_time_offset = true;
  /// Image velocity used by the time-offset correction: "motion_field" (from the gyro, the
  /// estimated velocity and the feature depth) or "tracked" (difference of the tracked positions,
  /// as the reference does; its noise correlates with the position noise and biases the offset).
  std::string time_offset_velocity = "motion_field";
  double time_offset_prior_sigma_s =
      0.005;  ///< [s] prior std of the time offset around the config value
  /// Estimate the rolling-shutter readout time online (a parameter of the window's reprojection
  /// factors, like the time offset); false: [camera] rolling_shutter_readout_s is a constant.
  bool estimate_rolling_shutter_readout = false;
  /// [s] prior std of the readout around [camera] rolling_shutter_readout_s (held until the first
  /// marginalisation, then inside the marginalisation prior, as the time offset's)
  double rolling_shutter_readout_prior_sigma_s = 0.02;
  /// [s] the estimate is kept within [0, this] (a weakly excited estimate cannot run away)
  double rolling_shutter_readout_max_s = 0.1;
  /// [Hz] rate of estimator updates; frames in between get IMU-propagated poses. 0 = every frame.
  double update_rate_hz = 15.0;
  double fail_max_acc_bias_m_s2 = 2.5;    ///< [m/s^2]
  double fail_max_gyr_bias_rad_s = 1.0;   ///< [rad/s]
  double fail_max_speed_m_s = 5.0;        ///< [m/s] estimated speed (state or between updates)
  double fail_max_jump_m = 5.0;           ///< [m]
  double fail_max_vertical_jump_m = 1.0;  ///< [m]
  /// A frame with fewer than fail_min_features features is blind (a covered lens, a blackout, a
  /// bare wall, motion blur): the IMU carries the pose from the newest frame that saw enough,
  /// and the first frame that sees again continues the window from there. After blind frames
  /// for longer than fail_max_blind_s tracking is lost instead (reset, re-initialisation when
  /// the images come back): the IMU alone drifts by centimetres per second.
  int fail_min_features = 10;     ///< [count]
  double fail_max_blind_s = 2.0;  ///< [s] 0 = never

  /// The virtual focal length [px] in which pixel thresholds above are expressed (VINS convention),
  /// so that the same config works for any camera resolution.
  static constexpr double kVirtualFocalPx = 460.0;

  WheelOptions wheel;  ///< the [wheel] section (doc/wheels.md)

  /// Reads [estimator] and [wheel].
  static EstimatorOptions load(IniReader& ini);
};

}  // namespace rgbdi::estimator
