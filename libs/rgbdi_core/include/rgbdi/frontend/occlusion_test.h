// Does a feature's tracking window straddle a depth discontinuity (an occlusion boundary)?
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

/// Fit of a plane to the depth around a feature. Inverse depth of a plane is an affine function
/// of the pixel coordinates (1/z = a u + b v + c), so a least-squares fit in inverse depth is
/// exact for every planar patch, however slanted (floors seen at grazing angles included), and
/// its residual measures how far the window is from one plane. With the sensor model
/// sigma_z = coeff z^2 the inverse-depth noise is the constant coeff [1/m] at every range.
struct WindowPlaneFit {
  int samples = 0;                  ///< valid depth samples in the window
  int grid_samples = 0;             ///< samples of the grid inside the image (valid or not)
  double rms_residual_inv_m = 0.0;  ///< RMS inverse-depth residual of the plane fit [1/m]
};

/// Samples `depth_m` (CV_32FC1, metres, 0 = no data) on a grid of step `step_px` within
/// `half_window_px` of the rounded `uv` and fits the inverse-depth plane. Samples outside the
/// image are skipped. Throws std::invalid_argument when `depth_m` is not CV_32FC1.
WindowPlaneFit fitWindowPlane(const cv::Mat& depth_m, const Eigen::Vector2d& uv, int half_window_px,
                              int step_px);

/// True when the KLT window of a feature at `uv` straddles an occlusion boundary: the plane fit
/// of its occlusion_window_px window leaves an RMS residual above occlusion_max_residual_sigmas
/// inverse-depth noise sigmas (depth_noise_coeff). Such a window holds two surfaces moving
/// differently in the image; KLT follows a blend of them, and the tracked point slides against
/// every 3-D point (on simulated tracked_slopes these features are 2 of 5 observations, their
/// mean error 7 px, and they bias the odometry's scale by 0.5 %). False when the check is off
/// (occlusion_window_px = 0) or fewer than occlusion_min_valid_fraction of the window's samples
/// have depth (nothing to judge by).
bool straddlesOcclusion(const cv::Mat& depth_m, const Eigen::Vector2d& uv,
                        const FrontendOptions& options);

}  // namespace rgbdi::frontend
