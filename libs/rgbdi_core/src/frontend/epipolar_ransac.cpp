#include "frontend/epipolar_ransac.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace rgbdi::frontend {
namespace {

/// Larger of the distances of b to the epipolar line F a and of a to the line F^T b [px].
double epipolarDistance(const cv::Matx33d& F, const cv::Point2f& a, const cv::Point2f& b) {
  const cv::Vec3d pa(a.x, a.y, 1.0), pb(b.x, b.y, 1.0);
  const cv::Vec3d line_b = F * pa, line_a = F.t() * pb;
  const double residual = std::abs(pb.dot(line_b));
  const double nb = std::hypot(line_b[0], line_b[1]), na = std::hypot(line_a[0], line_a[1]);
  if (nb <= 0.0 || na <= 0.0) return 0.0;  // degenerate line (a point at the epipole)
  return std::max(residual / nb, residual / na);
}

}  // namespace

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
    a[i] = cv::Point2f(float(cam.fx * previous_xn[i].x() + cam.cx),
                       float(cam.fy * previous_xn[i].y() + cam.cy));
    b[i] = cv::Point2f(float(cam.fx * current_xn[i].x() + cam.cx),
                       float(cam.fy * current_xn[i].y() + cam.cy));
  }
  cv::Mat mask;
  const cv::Mat F = cv::findFundamentalMat(a, b, cv::FM_RANSAC, threshold_px, confidence, mask);
  // No model (e.g. all points identical): keep everything rather than drop a whole frame.
  if (F.rows != 3 || F.cols != 3 || mask.empty()) return inliers;
  for (size_t i = 0; i < n; ++i) inliers[i] = mask.at<std::uint8_t>(static_cast<int>(i)) ? 1 : 0;

  // RANSAC's model comes from a minimal sample; its errors grow with parallax, so the nearest
  // (most informative) points are the first to fall off a 1-pixel band. Refit on all inliers by
  // least squares and classify again with the refined model.
  std::vector<cv::Point2f> ia, ib;
  for (size_t i = 0; i < n; ++i)
    if (inliers[i]) {
      ia.push_back(a[i]);
      ib.push_back(b[i]);
    }
  if (ia.size() < kMinEpipolarCorrespondences) return inliers;
  const cv::Mat refined = cv::findFundamentalMat(ia, ib, cv::FM_8POINT);
  if (refined.rows != 3 || refined.cols != 3) return inliers;
  const cv::Matx33d Fr(refined);
  std::vector<std::uint8_t> refit(n);
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    refit[i] = epipolarDistance(Fr, a[i], b[i]) <= threshold_px ? 1 : 0;
    kept += refit[i];
  }
  // A refit that explains fewer points than the sample model did is not an improvement.
  if (kept < ia.size()) return inliers;
  return refit;
}

}  // namespace rgbdi::frontend
