// Geometric outlier rejection between two images with a fundamental matrix fitted by RANSAC.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rgbdi/common/camera.h"

namespace rgbdi::frontend {

/// Minimum number of correspondences for the 8-point RANSAC; with fewer nothing is rejected.
constexpr size_t kMinEpipolarCorrespondences = 8;

/// Marks each correspondence (undistorted normalised coordinates in the previous and current
/// image) as inlier (1) or outlier (0) of a fundamental matrix found by RANSAC. The points are
/// scaled by the camera's focal lengths so `threshold_px` is an epipolar distance in pixels of an
/// undistorted image with this camera's focal length. OpenCV's RANSAC seeds its own generator
/// with a constant, so the result is deterministic.
std::vector<std::uint8_t> epipolarInliers(const std::vector<Eigen::Vector2d>& previous_xn,
                                          const std::vector<Eigen::Vector2d>& current_xn,
                                          const PinholeCamera& cam, double threshold_px,
                                          double confidence);

}  // namespace rgbdi::frontend
