#include "frontend/feature_spacing.h"

#include <algorithm>
#include <cmath>

namespace rgbdi::frontend {

FeatureSpacing::FeatureSpacing(int width, int height, double min_distance_px)
    : min_distance2_(min_distance_px * min_distance_px),
      cell_size_(min_distance_px),
      cells_x_(std::max(1, static_cast<int>(std::ceil(width / min_distance_px)))),
      cells_y_(std::max(1, static_cast<int>(std::ceil(height / min_distance_px)))),
      cells_(static_cast<size_t>(cells_x_) * cells_y_) {}

int FeatureSpacing::cellOf(float coordinate) const {
  return static_cast<int>(std::floor(coordinate / cell_size_));
}

bool FeatureSpacing::isFree(const cv::Point2f& p) const {
  const int cx = cellOf(p.x), cy = cellOf(p.y);
  for (int y = std::max(0, cy - 1); y <= std::min(cells_y_ - 1, cy + 1); ++y)
    for (int x = std::max(0, cx - 1); x <= std::min(cells_x_ - 1, cx + 1); ++x)
      for (const cv::Point2f& q : cells_[static_cast<size_t>(cellIndex(x, y))]) {
        const double dx = p.x - q.x, dy = p.y - q.y;
        if (dx * dx + dy * dy < min_distance2_) return false;
      }
  return true;
}

void FeatureSpacing::accept(const cv::Point2f& p) {
  // Points outside the image (callers drop those first) are clamped into the border cells so the
  // grid stays valid.
  const int cx = std::clamp(cellOf(p.x), 0, cells_x_ - 1);
  const int cy = std::clamp(cellOf(p.y), 0, cells_y_ - 1);
  cells_[static_cast<size_t>(cellIndex(cx, cy))].push_back(p);
}

}  // namespace rgbdi::frontend
