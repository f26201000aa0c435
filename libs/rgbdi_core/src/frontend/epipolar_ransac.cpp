#include "frontend/epipolar_ransac.h"

#include <opencv2/calib3d.hpp>

#include <stdexcept>

namespace rgbdi::frontend {

std::vector<std::uint8_t> epipolarInliers(const std::vector<Eigen::Vector2d>& previous_xn,
                                          const std::vector<Eigen::Vector2d>& current_xn,
                                          const PinholeCamera& cam, double threshold_px,
                                          double confidence) {
  if (previous_xn.size() != current_xn.size())
    throw std::invalid_argument("epipolarInliers: point lists differ in length");
  const size_t n = previous_xn.size();
  std::vector<std::uint8_t> inliers(n, 1);
  if (n < kMinEpipolarCorrespondences) return inliers;

  std::vector<cv::Point2f> a(n), b(n);
  for (size_t i = 0; i < n; ++i) {
    a[i] = cv::Point2f(float(cam.fx * previous_xn[i].x() + cam.cx), float(cam.fy * previous_xn[i].y() + cam.cy));
    b[i] = cv::Point2f(float(cam.fx * current_xn[i].x() + cam.cx), float(cam.fy * current_xn[i].y() + cam.cy));
  }
  cv::Mat mask;
  const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, threshold_px, confidence, mask);
  // No model (e.g. all points identical): keep everything rather than drop a whole frame.
  if (F.empty() || mask.empty()) return inliers;
  for (size_t i = 0; i < n; ++i) inliers[i] = mask.at<std::uint8_t>(static_cast<int>(i)) ? 1 : 0;
  return inliers;
}

}  // namespace rgbdi::frontend
