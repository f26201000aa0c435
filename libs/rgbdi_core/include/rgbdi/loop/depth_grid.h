// A coarse depth image of a keyframe for the free-space check of geometric verification: the
// colour-registered depth sampled on a regular grid of pixels (depth edges and holes left empty).
// A few kilobytes per keyframe instead of the image; enough to tell whether one keyframe's
// surfaces lie where the other keyframe saw through to something farther away.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace rgbdi::loop {

struct DepthGrid {
  int cols = 0;  ///< [count] samples per row (0 = no grid)
  int rows = 0;  ///< [count] sample rows
  /// [m] depth along the colour camera's optical axis at each sample, row-major; 0 = no depth
  /// (hole, depth edge, out of range).
  std::vector<float> depth_m;

  bool empty() const { return cols <= 0 || rows <= 0; }
  /// True when depth_m holds cols * rows values.
  bool consistent() const {
    return cols >= 0 && rows >= 0 &&
           depth_m.size() == static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows);
  }
  float at(int c, int r) const { return depth_m[static_cast<std::size_t>(r) * cols + c]; }
  /// Distorted colour pixel of sample (c, r) in an image of width x height: the centre of the
  /// grid cell, so the samples cover the image evenly.
  Eigen::Vector2d pixel(int c, int r, int width, int height) const {
    return {(c + 0.5) * width / cols, (r + 0.5) * height / rows};
  }
};

}  // namespace rgbdi::loop
