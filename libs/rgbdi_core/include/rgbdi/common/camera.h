// Pinhole camera with radial-tangential (OpenCV "plumb_bob") distortion.
#pragma once

#include <Eigen/Core>
#include <array>

namespace rgbdi {

struct PinholeCamera {
  int width = 0, height = 0;              ///< [px]
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< [px]
  /// k1, k2, p1, p2, k3 (OpenCV order). All zero = no distortion.
  std::array<double, 5> dist{0, 0, 0, 0, 0};

  bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }
  bool hasDistortion() const;

  /// Distort a normalised image point (x/z, y/z).
  Eigen::Vector2d distortNormalized(const Eigen::Vector2d& xn) const;
  /// Inverse of distortNormalized by fixed-point iteration (exact when there is no distortion).
  Eigen::Vector2d undistortNormalized(const Eigen::Vector2d& xd) const;

  /// Project a point in the camera optical frame (z forward) to distorted pixel coordinates.
  /// Returns false when the point is not in front of the camera.
  bool project(const Eigen::Vector3d& p_cam, Eigen::Vector2d& uv) const;
  /// Pixel (distorted) -> undistorted normalised coordinates (x/z, y/z).
  Eigen::Vector2d pixelToNormalized(const Eigen::Vector2d& uv) const;
  /// Pixel (distorted) + depth z [m] -> 3-D point in the camera optical frame.
  Eigen::Vector3d backProject(const Eigen::Vector2d& uv, double z) const;
  bool inImage(const Eigen::Vector2d& uv, double border = 0.0) const {
    return uv.x() >= border && uv.y() >= border && uv.x() <= width - 1 - border &&
           uv.y() <= height - 1 - border;
  }
};

}  // namespace rgbdi
