// Output of the visual front end for one image: tracked point features and tracking statistics.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace rgbdi::frontend {

/// One feature seen in one colour image.
struct FeatureObservation {
  std::uint64_t id = 0;  ///< unique per tracker, starts at 0, increases with detection order
  Eigen::Vector2d uv =
      Eigen::Vector2d::Zero();  ///< distorted pixel position in the colour image [px]
  Eigen::Vector2d xn = Eigen::Vector2d::Zero();  ///< undistorted normalised coordinates (x/z, y/z)
  /// d(xn)/dt between the previous and this image [1/s]; zero for a newly detected feature.
  /// Used by the estimator for the online camera-IMU time offset.
  Eigen::Vector2d velocity_xn = Eigen::Vector2d::Zero();
  double depth_m = 0.0;  ///< depth along the colour camera's optical axis [m]; 0 = no valid depth
  int track_length = 1;  ///< number of images this feature has been seen in, including this one
};

/// Thread CPU time of each front-end step for one image [ms] (diagnostics only).
struct FrontendTimings {
  double grey_ms = 0.0;     ///< colour -> grey conversion (and CLAHE when enabled)
  double pyramid_ms = 0.0;  ///< image pyramid with derivatives
  double klt_ms = 0.0;      ///< forward + backward KLT and border check
  double ransac_ms = 0.0;   ///< fundamental-matrix RANSAC
  double detect_ms = 0.0;   ///< distribution mask and Shi-Tomasi detection
  double depth_ms = 0.0;    ///< depth registration and per-feature sampling
  double total_ms = 0.0;    ///< the whole track() call
  /// Tracking + detection: the part with the 6 ms budget (everything except depth).
  double trackingMs() const { return grey_ms + pyramid_ms + klt_ms + ransac_ms + detect_ms; }
};

/// All features of one colour image, ordered by increasing id.
struct FeatureFrame {
  double t = 0.0;                 ///< stamp of the colour image [s]
  std::uint64_t frame_index = 0;  ///< RgbdFrame::index of the source image
  std::vector<FeatureObservation> features;

  int n_tracked = 0;          ///< features carried over from the previous image
  int n_new = 0;              ///< features detected in this image
  int n_klt_lost = 0;         ///< lost by KLT (no convergence or forward-backward mismatch)
  int n_border_rejected = 0;  ///< tracked too close to (or beyond) the image border
  /// dropped because no pixel of the image reaches the texture floor (min_gradient_grey_per_px):
  /// the view lost its texture (a bare wall, the lights going out)
  int n_low_texture = 0;
  int n_ransac_rejected = 0;  ///< rejected as outliers of the fundamental matrix
  int n_too_close = 0;        ///< dropped because a longer-tracked feature is within min distance
  int n_occluded = 0;  ///< tracked features dropped: their window straddles an occlusion boundary
  int n_occluded_skipped = 0;  ///< corners not taken as new features for the same reason
  int n_with_depth = 0;        ///< features with depth_m > 0
  FrontendTimings timings;
};

}  // namespace rgbdi::frontend
