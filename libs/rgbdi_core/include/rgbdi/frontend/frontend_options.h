// Options of the visual front end: the [frontend] section of the configuration.
#pragma once

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::frontend {

/// Tracker, outlier-rejection and depth-sampling parameters. Defaults equal share/config.ini.
struct FrontendOptions {
  // --- feature count and distribution ---
  int max_features = 150;  ///< [count] features kept per frame
  /// [count] new corners are detected only when at least this many of max_features are missing
  /// (1: on every image that lost a feature, as VINS). Detection (the corner response over the
  /// whole image, its local maxima) was a tenth of the CPU with 1, for the one or two features
  /// most images lose; with a few missing first it runs on a fraction of the images.
  int detect_min_missing = 1;
  double min_distance_px = 15.0;     ///< [px] no two features closer than this
  double shi_tomasi_quality = 0.01;  ///< [unitless] corner threshold relative to the best corner
  int shi_tomasi_block_size = 3;     ///< [px] window of the corner (min eigenvalue) measure
  /// [grey levels/px] absolute texture floor: a new corner's smaller structure-tensor eigenvalue
  /// per pixel of its block must reach the square of this, and an image where no pixel does
  /// keeps no track (KLT converges on sensor noise too). The relative threshold alone takes
  /// sensor-noise blobs of a textureless view (a bare wall) for corners: i.i.d. noise of sigma
  /// grey levels peaks at about 0.9 sigma here, textured corners at tens. 0 = no floor.
  double min_gradient_grey_per_px = 2.0;
  int border_px = 1;  ///< [px] features closer than this to the image edge are dropped
  /// [unitless] CLAHE contrast limit applied to the grey image before tracking; 0 disables it.
  double clahe_clip_limit = 0.0;

  // --- KLT tracking ---
  int klt_window_px = 15;        ///< [px] side of the KLT window
  int klt_pyramid_levels = 3;    ///< [count] pyramid levels above the base image
  int klt_max_iterations = 30;   ///< [count] Gauss-Newton iterations per level
  double klt_epsilon_px = 0.01;  ///< [px] stop iterating when the update is smaller
  /// [px] a feature is dropped when tracking it back to the previous image misses its start by
  /// more.
  double klt_max_forward_backward_px = 0.5;
  /// Features that the gyroscope's rotation since the previous image (when the caller passes it:
  /// VioSystem does) moves beyond the pyramid's reach, klt_window_px / 2 * 2^klt_pyramid_levels,
  /// start KLT where the rotation puts them instead of at their previous position (a robot
  /// spinning in place, a whip pan); nearer ones start as without it.
  bool klt_predict_rotation = true;
  /// With klt_predict_rotation: the prediction also moves each feature with the camera's
  /// translation (the estimated velocity at the previous image dead-reckoned with the IMU) at its
  /// depth in the previous image, so features of near surfaces passed fast start where they went.
  bool klt_predict_translation = true;
  /// Start every feature where the prediction puts it, not only those it moves beyond the
  /// pyramid's reach (klt_window_px / 2 x 2^klt_pyramid_levels).
  bool klt_predict_every_feature = false;

  // --- geometric outlier rejection ---
  double ransac_threshold_px = 1.0;  ///< [px] epipolar distance at the camera's focal length
  double ransac_confidence = 0.99;   ///< [unitless] RANSAC success probability

  // --- per-feature depth ---
  double depth_min_m = 0.1;  ///< [m] nearest accepted feature depth
  /// [m] farthest accepted feature depth: the sensor's useful range. The estimator applies its
  /// own, tighter gates (depth verification 3 m, initialisation 10 m).
  double depth_max_m = 10.0;
  int depth_neighbourhood_px = 2;           ///< [px] half-size of the hole/edge check window
  double depth_max_relative_spread = 0.03;  ///< [unitless] (max-min)/median allowed in that window
  /// [1/m] sensor depth noise sigma = coeff * z^2 (D435: ~0.004). The window's spread may reach
  /// depth_max_noise_sigmas of this noise before it counts as a depth edge, so that noise alone
  /// never rejects a feature at range; 0 disables the allowance.
  double depth_noise_coeff = 0.004;
  double depth_max_noise_sigmas = 5.0;  ///< [unitless]
  /// Occlusion boundaries (rgbdi/frontend/occlusion_test.h): a feature whose KLT window holds two
  /// surfaces (the inverse-depth plane fit of the window leaves more than
  /// occlusion_max_residual_sigmas of depth noise) is not detected there and is dropped when a
  /// tracked one comes to straddle one. 0 turns the check off.
  int occlusion_window_px = 10;      ///< [px] half-size of the checked window (KLT window / 2)
  int occlusion_sample_step_px = 2;  ///< [px] pixel step of the depth samples in that window
  double occlusion_max_residual_sigmas = 5.0;  ///< [unitless] RMS plane residual allowed, in sigmas
  double occlusion_min_valid_fraction = 0.5;   ///< [unitless] samples with depth needed to judge
  /// [unitless] depth registration: a crack pixel is filled only when its two opposite neighbours
  /// agree within this fraction of their depth.
  double registration_fill_max_relative_diff = 0.02;

  /// [count] threads OpenCV may use for the image operations (a process-wide OpenCV setting,
  /// applied by applyOpenCvThreads: when a FeatureTracker is built, and by the SLAM system before
  /// its threads start). 1 = on the calling thread: OpenCV's worker pool spins between the
  /// short calls of each frame and burns a second core for no gain (doc/performance.md); 0 =
  /// leave OpenCV's default (one thread per core).
  int opencv_threads = 1;

  /// Throws ConfigError when fields are inconsistent with each other or out of their ranges.
  void validate() const;
  /// Reads [frontend]; missing keys keep the defaults above.
  static FrontendOptions load(IniReader& ini);
};

/// Sets OpenCV's thread count to options.opencv_threads (0: leaves it) unless it is that already.
/// Changing it rebuilds OpenCV's process-wide worker pool, which must not happen while another
/// thread runs an OpenCV operation (with the TBB backend both threads then spin forever): a
/// program applies it once before its threads start, and later calls with the same options do
/// nothing.
void applyOpenCvThreads(const FrontendOptions& options);

}  // namespace rgbdi::frontend
