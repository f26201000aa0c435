#include "frontend/corner_detector.h"

#include <algorithm>
#include <opencv2/core/hal/hal.hpp>
#include <stdexcept>

#include "frontend/feature_spacing.h"

namespace rgbdi::frontend {

void CornerDetector::computeResponse(const cv::Mat& derivatives, int block_size) {
  if (derivatives.type() != CV_16SC2)
    throw std::invalid_argument("CornerDetector: need CV_16SC2 derivatives");
  if (block_size < 1) throw std::invalid_argument("CornerDetector: block size must be positive");
  block_size_ = block_size;
  const int w = derivatives.cols, h = derivatives.rows, half = block_size / 2;
  // Pixels closer than half a block to the border have no complete window: response 0 there.
  response_.create(h, w, CV_32FC1);
  response_.setTo(0.0f);
  if (w < block_size || h < block_size) return;

  // One pass over the image: per row the three structure-tensor products are summed along the
  // row, kept in a ring of `block_size` rows, and the rows of the ring are summed into the
  // window sums of the middle row. No image-sized temporaries, every loop vectorises.
  const size_t row_len = static_cast<size_t>(w);
  ring_.assign(static_cast<size_t>(block_size) * 3 * row_len, 0.0f);
  products_.resize(3 * row_len);
  sums_.resize(4 * row_len);
  float* __restrict pxx = products_.data();
  float* __restrict pxy = pxx + row_len;
  float* __restrict pyy = pxy + row_len;
  float* __restrict a = sums_.data();
  float* __restrict b = a + row_len;
  float* __restrict c = b + row_len;
  float* __restrict root = c + row_len;

  for (int v = 0; v < h; ++v) {
    const short* __restrict d = derivatives.ptr<short>(v);
    for (int u = 0; u < w; ++u) {
      const float ix = d[2 * u], iy = d[2 * u + 1];
      pxx[u] = ix * ix;
      pxy[u] = ix * iy;
      pyy[u] = iy * iy;
    }
    float* __restrict slot = ring_.data() + static_cast<size_t>(v % block_size) * 3 * row_len;
    for (int plane = 0; plane < 3; ++plane) {
      const float* __restrict p = products_.data() + plane * row_len;
      float* __restrict s = slot + plane * row_len;
      // Shifted adds (offset outside, pixels inside) so the pixel loop vectorises.
      for (int u = half; u < w - half; ++u) s[u] = p[u - half];
      for (int k = 1; k < block_size; ++k)
        for (int u = half; u < w - half; ++u) s[u] += p[u - half + k];
    }
    if (v < block_size - 1) continue;

    // Window sums of row v - half: the ring holds rows v - block_size + 1 .. v.
    std::fill(sums_.begin(), sums_.begin() + static_cast<std::ptrdiff_t>(3 * row_len), 0.0f);
    for (int k = 0; k < block_size; ++k) {
      const float* __restrict s = ring_.data() + static_cast<size_t>(k) * 3 * row_len;
      for (size_t i = 0; i < 3 * row_len; ++i) a[i] += s[i];
    }
    // Smaller eigenvalue of [a b; b c]: (a + c) / 2 - sqrt(((a - c) / 2)^2 + b^2). The root goes
    // through OpenCV's vectorised routine (std::sqrt in a loop stays scalar for errno's sake).
    for (int u = 0; u < w; ++u) {
      const float half_diff = 0.5f * (a[u] - c[u]);
      root[u] = half_diff * half_diff + b[u] * b[u];
    }
    cv::hal::sqrt32f(root, root, w);
    float* __restrict r = response_.ptr<float>(v - half);
    for (int u = half; u < w - half; ++u) r[u] = 0.5f * (a[u] + c[u]) - root[u];
  }
}

double CornerDetector::responseFloor(int block_size, double min_gradient) {
  // The response sums the squared Scharr derivatives over block_size^2 pixels.
  return kScharrScale * kScharrScale * block_size * block_size * min_gradient * min_gradient;
}

bool CornerDetector::hasCorner(double min_gradient) const {
  double strongest = 0.0;
  cv::minMaxLoc(response_, nullptr, &strongest);
  return strongest >= responseFloor(block_size_, min_gradient);
}

std::vector<cv::Point2f> CornerDetector::detect(const cv::Mat& mask, int max_corners,
                                                double quality, double min_gradient,
                                                FeatureSpacing& spacing) {
  if (mask.type() != CV_8UC1 || mask.size() != response_.size())
    throw std::invalid_argument(
        "CornerDetector: need a CV_8UC1 mask of the size of the last computeResponse() image");
  std::vector<cv::Point2f> corners;
  candidates_.clear();  // detectMore() never continues the candidates of an earlier image
  next_candidate_ = 0;
  if (max_corners <= 0) return corners;

  double strongest = 0.0;
  cv::minMaxLoc(response_, nullptr, &strongest, nullptr, nullptr, mask);
  const double floor = responseFloor(block_size_, min_gradient);
  if (!(strongest > 0.0) || strongest < floor) return corners;  // flat, bare, or nothing allowed
  const float threshold = static_cast<float>(std::max(quality * strongest, floor));

  // Candidates: allowed 3x3 local maxima at or above the threshold.
  const int w = response_.cols, h = response_.rows;
  for (int v = 1; v + 1 < h; ++v) {
    const float* up = response_.ptr<float>(v - 1);
    const float* r = response_.ptr<float>(v);
    const float* down = response_.ptr<float>(v + 1);
    const std::uint8_t* allowed = mask.ptr<std::uint8_t>(v);
    for (int u = 1; u + 1 < w; ++u) {
      const float x = r[u];
      if (x < threshold || !allowed[u]) continue;
      if (x < r[u - 1] || x < r[u + 1] || x < up[u - 1] || x < up[u] || x < up[u + 1] ||
          x < down[u - 1] || x < down[u] || x < down[u + 1])
        continue;
      candidates_.push_back({x, u, v});
    }
  }
  std::sort(candidates_.begin(), candidates_.end(), [](const Candidate& p, const Candidate& q) {
    if (p.response != q.response) return p.response > q.response;
    return p.v != q.v ? p.v < q.v : p.u < q.u;
  });
  return detectMore(max_corners, spacing);
}

std::vector<cv::Point2f> CornerDetector::detectMore(int max_corners, FeatureSpacing& spacing) {
  std::vector<cv::Point2f> corners;
  while (static_cast<int>(corners.size()) < max_corners && next_candidate_ < candidates_.size()) {
    const Candidate& cand = candidates_[next_candidate_++];
    const cv::Point2f p(static_cast<float>(cand.u), static_cast<float>(cand.v));
    if (!spacing.isFree(p)) continue;
    spacing.accept(p);
    corners.push_back(p);
  }
  return corners;
}

}  // namespace rgbdi::frontend
