// trajectory.png: top view (x-y, equal axes) and side view (x-z) of the estimated trajectory,
// with the ground truth and the estimate coloured by its position error when ground truth is
// given. Drawn with OpenCV, no GUI.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <opencv2/core.hpp>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/mapping_options.h"

namespace rgbdi::mapping {

/// World-to-pixel mapping of one view panel.
struct PlotPanel {
  std::string title;
  cv::Rect area;                    ///< panel rectangle in the image [px]
  int axis_h = 0, axis_v = 1;       ///< world axes (0 x, 1 y, 2 z) shown horizontally / vertically
  double h_min = 0.0, v_min = 0.0;  ///< world values at the left / bottom edge [m]
  double px_per_m_h = 1.0, px_per_m_v = 1.0;  ///< scales [px/m]
  /// Pixel (column, row) of a world point.
  Eigen::Vector2d toPixel(const Eigen::Vector3d& p_world) const;
};

/// What was drawn.
struct TrajectoryPlotInfo {
  int width = 0, height = 0;        ///< image size [px]
  std::array<PlotPanel, 2> panels;  ///< [0] top view (x, y), [1] side view (x, z)
  std::size_t matched = 0;          ///< estimated poses with a ground-truth pose within tolerance
  double rmse_m = 0.0;              ///< position error of the matched poses (as given to the plot)
  double max_error_m = 0.0;
};

/// Draws and writes the PNG atomically. `ground_truth` (nullable) must already be expressed in
/// the estimate's frame (aligned by the caller). Throws std::invalid_argument for an empty or
/// non-finite estimate / ground truth, IoError when the file cannot be written.
/// `alignment` names how the caller aligned the ground truth (printed under the plot, e.g.
/// "ground truth aligned to the estimate: position + yaw").
TrajectoryPlotInfo plotTrajectory(const std::string& path, const Trajectory& estimate,
                                  const Trajectory* ground_truth,
                                  const TrajectoryPlotOptions& options,
                                  const std::string& alignment = "no alignment applied");

}  // namespace rgbdi::mapping
