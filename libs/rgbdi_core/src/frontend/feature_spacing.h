// Exact minimum-distance test between image points, using a grid of cells of that size so each
// query looks at the 3x3 surrounding cells only.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace rgbdi::frontend {

class FeatureSpacing {
 public:
  FeatureSpacing(int width, int height, double min_distance_px);

  /// True when no accepted point is closer than min_distance_px to `p`.
  bool isFree(const cv::Point2f& p) const;
  void accept(const cv::Point2f& p);

 private:
  int cellIndex(int cx, int cy) const { return cy * cells_x_ + cx; }
  int cellOf(float coordinate) const;

  double min_distance2_;
  double cell_size_;
  int cells_x_, cells_y_;
  std::vector<std::vector<cv::Point2f>> cells_;
};

}  // namespace rgbdi::frontend
