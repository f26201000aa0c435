// Robust depth of one feature from a depth image registered to the colour image.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

/// Depth [m] at the sub-pixel position `uv` of `depth_m` (CV_32FC1, metres, 0 = no data), or 0
/// when it cannot be trusted. The value is bilinearly interpolated from the four surrounding
/// pixels (nearest pixel when depth_neighbourhood_px is 0). Rejected (0) when:
///  - the window of half-size depth_neighbourhood_px around the nearest pixel (plus the four
///    interpolation pixels) leaves the image or contains a hole;
///  - the window spans a depth discontinuity: (max - min) / median > depth_max_relative_spread
///    (features on depth edges are the classic source of wrong depths);
///  - the interpolated depth is outside [depth_min_m, depth_max_m].
/// Throws std::invalid_argument when `depth_m` is not CV_32FC1.
double sampleDepth(const cv::Mat& depth_m, const Eigen::Vector2d& uv,
                   const FrontendOptions& options);

}  // namespace rgbdi::frontend
