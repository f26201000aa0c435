#include "frontend/corner_detector.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "frontend/feature_spacing.h"

namespace rgbdi::frontend {

std::vector<cv::Point2f> CornerDetector::detect(const cv::Mat& derivatives, const cv::Mat& mask, int max_corners,
                                                double quality, int block_size, FeatureSpacing& spacing) {
  if (derivatives.type() != CV_16SC2 || mask.type() != CV_8UC1 || mask.size() != derivatives.size())
    throw std::invalid_argument("CornerDetector: need CV_16SC2 derivatives and a CV_8UC1 mask of the same size");
  std::vector<cv::Point2f> corners;
  if (max_corners <= 0) return corners;
  const int w = derivatives.cols, h = derivatives.rows;

  // Structure tensor entries per pixel (Ix^2, Ix Iy, Iy^2), in three planes so that the loops
  // vectorise.
  for (cv::Mat* m : {&xx_, &xy_, &yy_}) m->create(h, w, CV_32FC1);
  for (int v = 0; v < h; ++v) {
    const short* __restrict d = derivatives.ptr<short>(v);
    float* __restrict xx = xx_.ptr<float>(v);
    float* __restrict xy = xy_.ptr<float>(v);
    float* __restrict yy = yy_.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const float ix = d[2 * u], iy = d[2 * u + 1];
      xx[u] = ix * ix;
      xy[u] = ix * iy;
      yy[u] = iy * iy;
    }
  }
  const cv::Size block(block_size, block_size);
  cv::boxFilter(xx_, sum_xx_, -1, block, cv::Point(-1, -1), false, cv::BORDER_REFLECT_101);
  cv::boxFilter(xy_, sum_xy_, -1, block, cv::Point(-1, -1), false, cv::BORDER_REFLECT_101);
  cv::boxFilter(yy_, sum_yy_, -1, block, cv::Point(-1, -1), false, cv::BORDER_REFLECT_101);

  // Smaller eigenvalue of [a b; b c].
  response_.create(h, w, CV_32FC1);
  for (int v = 0; v < h; ++v) {
    const float* __restrict a = sum_xx_.ptr<float>(v);
    const float* __restrict b = sum_xy_.ptr<float>(v);
    const float* __restrict c = sum_yy_.ptr<float>(v);
    float* __restrict r = response_.ptr<float>(v);
    for (int u = 0; u < w; ++u) {
      const float half_diff = 0.5f * (a[u] - c[u]);
      r[u] = 0.5f * (a[u] + c[u]) - std::sqrt(half_diff * half_diff + b[u] * b[u]);
    }
  }

  double strongest = 0.0;
  cv::minMaxLoc(response_, nullptr, &strongest, nullptr, nullptr, mask);
  if (!(strongest > 0.0)) return corners;  // flat image, or nothing allowed
  const float threshold = static_cast<float>(quality * strongest);
  cv::dilate(response_, dilated_, cv::Mat());

  candidates_.clear();
  for (int v = 1; v + 1 < h; ++v) {
    const float* r = response_.ptr<float>(v);
    const float* m = dilated_.ptr<float>(v);
    const std::uint8_t* allowed = mask.ptr<std::uint8_t>(v);
    for (int u = 1; u + 1 < w; ++u)
      if (r[u] >= threshold && r[u] == m[u] && allowed[u]) candidates_.push_back({r[u], u, v});
  }
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& x, const Candidate& y) {
    if (x.response != y.response) return x.response > y.response;
    return x.v != y.v ? x.v < y.v : x.u < y.u;
  });
  for (const Candidate& c : candidates_) {
    const cv::Point2f p(static_cast<float>(c.u), static_cast<float>(c.v));
    if (!spacing.isFree(p)) continue;
    spacing.accept(p);
    corners.push_back(p);
    if (static_cast<int>(corners.size()) == max_corners) break;
  }
  return corners;
}

}  // namespace rgbdi::frontend
