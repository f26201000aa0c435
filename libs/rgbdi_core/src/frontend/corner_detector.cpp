#include "rgbdi/frontend/corner_detector.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <opencv2/core/hal/hal.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "common/cpu_dispatch.h"
#include "frontend/feature_spacing.h"

// The response is the front end's largest own cost per image; its loops are element-wise float
// arithmetic, which AVX2 does eight values at a time instead of SSE2's four. The row kernel is
// compiled for both and the AVX2 copy used when the CPU has it: the same operations in the same
// order (no FMA contraction without the FMA target), so the same values either way.

namespace rgbdi::frontend {

namespace {
/// Row v of CV_16SC2 Scharr derivatives (dI/dx, dI/dy interleaved) as two float rows.
struct InterleavedRows {
  const cv::Mat& derivatives;
  void operator()(int v, float* __restrict ix, float* __restrict iy) const {
    const short* __restrict d = derivatives.ptr<short>(v);
    for (int u = 0; u < derivatives.cols; ++u) {
      ix[u] = d[2 * u];
      iy[u] = d[2 * u + 1];
    }
  }
};

void requireDerivatives(const cv::Mat& derivatives) {
  if (derivatives.type() != CV_16SC2)
    throw std::invalid_argument("CornerDetector: need CV_16SC2 derivatives");
}
}  // namespace

float CornerResponse::compute(const cv::Mat& derivatives, int block_size, cv::Mat& response) {
  requireDerivatives(derivatives);
  return computeRows(derivatives.cols, derivatives.rows, block_size, InterleavedRows{derivatives},
                     &response, std::numeric_limits<float>::infinity());
}

bool CornerResponse::reaches(const cv::Mat& derivatives, int block_size, float floor) {
  requireDerivatives(derivatives);
  // Every response is >= 0 (the border's zeros among them), as compute() returns.
  if (!(floor > 0.0f)) return true;
  return computeRows(derivatives.cols, derivatives.rows, block_size, InterleavedRows{derivatives},
                     nullptr, floor) >= floor;
}

namespace {
/// One row's share of the response (see computeRows): its structure-tensor products summed
/// along the row into the ring slot of row v and, once the ring holds block_size rows, the
/// response of row v - half with the per-column maxima.
struct RowPass {
  int w, block_size, half, v;
  const float* ix;
  const float* iy;
  float* products;  ///< 3 x w
  float* ring;      ///< block_size x 3 x w
  float* sums;      ///< 4 x w: a, b, c and the square-root row
  float* response;  ///< row v - half of the response image
  float* column_max;
};

inline __attribute__((always_inline)) void rowPassInline(const RowPass& p) {
  const int w = p.w, half = p.half, block_size = p.block_size;
  const size_t row_len = static_cast<size_t>(w);
  float* __restrict pxx = p.products;
  float* __restrict pxy = pxx + row_len;
  float* __restrict pyy = pxy + row_len;
  const float* __restrict ix = p.ix;
  const float* __restrict iy = p.iy;
  for (int u = 0; u < w; ++u) {
    pxx[u] = ix[u] * ix[u];
    pxy[u] = ix[u] * iy[u];
    pyy[u] = iy[u] * iy[u];
  }
  float* __restrict slot = p.ring + static_cast<size_t>(p.v % block_size) * 3 * row_len;
  for (int plane = 0; plane < 3; ++plane) {
    const float* __restrict q = p.products + plane * row_len;
    float* __restrict s = slot + plane * row_len;
    // Shifted adds (offset outside, pixels inside) so the pixel loop vectorises.
    for (int u = half; u < w - half; ++u) s[u] = q[u - half];
    for (int k = 1; k < block_size; ++k)
      for (int u = half; u < w - half; ++u) s[u] += q[u - half + k];
  }
  if (p.v < block_size - 1) return;

  // Window sums of row v - half: the ring holds rows v - block_size + 1 .. v.
  float* __restrict a = p.sums;
  float* __restrict b = a + row_len;
  float* __restrict c = b + row_len;
  float* __restrict root = c + row_len;
  std::fill(a, a + 3 * row_len, 0.0f);
  for (int k = 0; k < block_size; ++k) {
    const float* __restrict s = p.ring + static_cast<size_t>(k) * 3 * row_len;
    for (size_t i = 0; i < 3 * row_len; ++i) a[i] += s[i];
  }
  // Smaller eigenvalue of [a b; b c]: (a + c) / 2 - sqrt(((a - c) / 2)^2 + b^2). The root goes
  // through OpenCV's vectorised routine (std::sqrt in a loop stays scalar for errno's sake).
  for (int u = 0; u < w; ++u) {
    const float half_diff = 0.5f * (a[u] - c[u]);
    root[u] = half_diff * half_diff + b[u] * b[u];
  }
  cv::hal::sqrt32f(root, root, w);
  float* __restrict r = p.response;
  float* __restrict column_max = p.column_max;
  std::fill_n(r, half, 0.0f);
  std::fill_n(r + w - half, half, 0.0f);
  for (int u = half; u < w - half; ++u) {
    r[u] = 0.5f * (a[u] + c[u]) - root[u];
    // Per column (an element-wise max vectorises, a running maximum would not).
    column_max[u] = std::max(column_max[u], r[u]);
  }
}

void rowPassPortable(const RowPass& p) { rowPassInline(p); }

#ifdef RGBDI_HAVE_X86_DISPATCH
__attribute__((target("avx2"))) void rowPassAvx2(const RowPass& p) { rowPassInline(p); }
#endif

using RowPassFunction = void (*)(const RowPass&);

RowPassFunction rowPassForThisCpu() {
#ifdef RGBDI_HAVE_X86_DISPATCH
  if (__builtin_cpu_supports("avx2")) return rowPassAvx2;
#endif
  return rowPassPortable;
}
}  // namespace

template <typename RowDerivatives>
float CornerResponse::computeRows(int w, int h, int block_size, RowDerivatives derivative,
                                  cv::Mat* response, float stop_at) {
  if (block_size < 1) throw std::invalid_argument("CornerDetector: block size must be positive");
  const int half = block_size / 2;
  // Pixels closer than half a block to the border have no complete window: response 0 there.
  if (response) response->create(h, w, CV_32FC1);
  if (w < block_size || h < block_size) {
    if (response) response->setTo(0.0f);
    return 0.0f;
  }
  // Only the border is zeroed here (rows now, columns with each row below): the image is reused
  // from frame to frame and the rest is overwritten.
  if (response)
    for (int v = 0; v < half; ++v) {
      std::fill_n(response->ptr<float>(v), w, 0.0f);
      std::fill_n(response->ptr<float>(h - 1 - v), w, 0.0f);
    }

  // One pass over the image: per row the three structure-tensor products are summed along the
  // row, kept in a ring of `block_size` rows, and the rows of the ring are summed into the
  // window sums of the middle row. No image-sized temporaries, every loop vectorises.
  const size_t row_len = static_cast<size_t>(w);
  ring_.assign(static_cast<size_t>(block_size) * 3 * row_len, 0.0f);
  products_.resize(3 * row_len);
  sums_.resize(4 * row_len);
  ix_.resize(row_len);
  iy_.resize(row_len);
  if (!response) scratch_row_.resize(row_len);
  column_max_.assign(row_len, 0.0f);  // the border's zeros count, as in the response image
  static const RowPassFunction row_pass = rowPassForThisCpu();
  RowPass pass{w,
               block_size,
               half,
               0,
               ix_.data(),
               iy_.data(),
               products_.data(),
               ring_.data(),
               sums_.data(),
               nullptr,
               column_max_.data()};
  // Whether to stop is checked every few response rows: the check is a pass over the column
  // maxima, a tenth of a row's own work.
  constexpr int kStopCheckRows = 16;
  const bool may_stop = stop_at < std::numeric_limits<float>::infinity();
  for (int v = 0; v < h; ++v) {
    derivative(v, ix_.data(), iy_.data());
    pass.v = v;
    pass.response = v < block_size - 1 ? nullptr
                    : response         ? response->ptr<float>(v - half)
                                       : scratch_row_.data();
    row_pass(pass);
    if (may_stop && v >= block_size - 1 && (v - block_size + 1) % kStopCheckRows == 0) {
      const float strongest = *std::max_element(column_max_.begin(), column_max_.end());
      if (strongest >= stop_at) return strongest;
    }
  }
  return *std::max_element(column_max_.begin(), column_max_.end());
}

void CornerCandidates::collect(const cv::Mat& response, float min_response, const cv::Mat* mask,
                               std::vector<CornerCandidate>& out) {
  const int w = response.cols, h = response.rows;
  if (w < 3 || h < 3) return;
  // A pixel at least as strong as its 8 neighbours equals the maximum of its 3x3 neighbourhood
  // (cv::dilate, vectorised): the test becomes three comparisons per pixel, which vectorise too,
  // and the rows are then skimmed eight pixels at a time for the few candidates.
  cv::dilate(response, neighbourhood_max_, cv::Mat());
  keep_.assign(static_cast<size_t>(w) + 8, 0);  // padded: the skim reads whole 8-byte words
  std::uint8_t* __restrict keep = keep_.data();
  for (int v = 1; v + 1 < h; ++v) {
    const float* __restrict r = response.ptr<float>(v);
    const float* __restrict m = neighbourhood_max_.ptr<float>(v);
    for (int u = 1; u + 1 < w; ++u)
      keep[u] = static_cast<std::uint8_t>((r[u] >= min_response) & (r[u] >= m[u]));
    if (mask) {
      const std::uint8_t* __restrict allowed = mask->ptr<std::uint8_t>(v);
      for (int u = 1; u + 1 < w; ++u) keep[u] &= static_cast<std::uint8_t>(allowed[u] != 0);
    }
    for (int u = 1; u + 1 < w; u += 8) {
      std::uint64_t word;
      std::memcpy(&word, keep + u, sizeof word);
      if (!word) continue;
      for (int k = u; k < std::min(u + 8, w - 1); ++k)
        if (keep[k]) out.push_back({r[k], k, v});
    }
  }
}

void CornerDetector::computeResponse(const cv::Mat& derivatives, int block_size) {
  computer_.compute(derivatives, block_size, response_);
  block_size_ = block_size;
}

double CornerDetector::responseFloor(int block_size, double min_gradient) {
  // The response sums the squared Scharr derivatives over block_size^2 pixels.
  return kScharrScale * kScharrScale * block_size * block_size * min_gradient * min_gradient;
}

bool CornerDetector::hasCorner(const cv::Mat& derivatives, int block_size, double min_gradient) {
  return computer_.reaches(derivatives, block_size,
                           static_cast<float>(responseFloor(block_size, min_gradient)));
}

std::vector<cv::Point2f> CornerDetector::detect(const cv::Mat& mask, int max_corners,
                                                double quality, double min_gradient,
                                                FeatureSpacing& spacing) {
  if (mask.type() != CV_8UC1 || mask.size() != response_.size())
    throw std::invalid_argument(
        "CornerDetector: need a CV_8UC1 mask of the size of the last computeResponse() image");
  std::vector<cv::Point2f> corners;
  candidates_.clear();  // detectMore() never continues the candidates of an earlier image
  next_candidate_ = sorted_end_ = 0;
  if (max_corners <= 0) return corners;

  // Strongest allowed response: per column first (an element-wise max vectorises; cv::minMaxLoc
  // with a mask tests pixel by pixel). A mask allowing nothing, or only responses <= 0, gives 0.
  const int w = response_.cols, h = response_.rows;
  column_max_.assign(static_cast<size_t>(w), 0.0f);
  float* __restrict column_max = column_max_.data();
  for (int v = 0; v < h; ++v) {
    const float* __restrict r = response_.ptr<float>(v);
    const std::uint8_t* __restrict allowed = mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < w; ++u) column_max[u] = std::max(column_max[u], allowed[u] ? r[u] : 0.0f);
  }
  const double strongest = *std::max_element(column_max_.begin(), column_max_.end());
  const double floor = responseFloor(block_size_, min_gradient);
  if (!(strongest > 0.0) || strongest < floor) return corners;  // flat, bare, or nothing allowed
  const float threshold = static_cast<float>(std::max(quality * strongest, floor));

  // Candidates: allowed 3x3 local maxima at or above the threshold, in scan order; detectMore()
  // takes them strongest first (none is sorted yet: sorted_end_ was reset above).
  collector_.collect(response_, threshold, &mask, candidates_);
  return detectMore(max_corners, spacing);
}

std::vector<cv::Point2f> CornerDetector::detectMore(int max_corners, FeatureSpacing& spacing) {
  std::vector<cv::Point2f> corners;
  while (static_cast<int>(corners.size()) < max_corners && next_candidate_ < candidates_.size()) {
    if (next_candidate_ == sorted_end_) {
      // Sorted a chunk at a time: a few corners are wanted from thousands of candidates, and
      // the strongest chunk in order is what a full sort would put first (a total order).
      const size_t chunk = std::max<size_t>(64, 4 * static_cast<size_t>(max_corners));
      const auto first = candidates_.begin() + static_cast<std::ptrdiff_t>(sorted_end_);
      const auto last = candidates_.begin() + static_cast<std::ptrdiff_t>(std::min(
                                                  candidates_.size(), sorted_end_ + chunk));
      std::nth_element(first, last - 1, candidates_.end(), CornerCandidates::strongerFirst);
      std::sort(first, last, CornerCandidates::strongerFirst);
      sorted_end_ = static_cast<size_t>(last - candidates_.begin());
    }
    const CornerCandidate& cand = candidates_[next_candidate_++];
    const cv::Point2f p(static_cast<float>(cand.u), static_cast<float>(cand.v));
    if (!spacing.isFree(p)) continue;
    spacing.accept(p);
    corners.push_back(p);
  }
  return corners;
}

}  // namespace rgbdi::frontend
