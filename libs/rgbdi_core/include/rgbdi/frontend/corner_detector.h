// Shi-Tomasi corner detection from image derivatives that the KLT pyramid already holds.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace rgbdi::frontend {

class FeatureSpacing;

/// A 3x3 local maximum of the corner response (at least its 8 neighbours), at pixel (u, v).
struct CornerCandidate {
  float response;
  int u, v;
};

/// Corner candidates of a response image: its 3x3 local maxima. Work buffers are kept between
/// calls.
class CornerCandidates {
 public:
  /// Appends the 3x3 local maxima of `response` (at least each of their 8 neighbours; none on
  /// the outermost pixel rows and columns) with a response of at least `min_response` where
  /// `mask` (CV_8UC1, nullptr: everywhere) is nonzero, in scan order (row, then column).
  void collect(const cv::Mat& response, float min_response, const cv::Mat* mask,
               std::vector<CornerCandidate>& out);
  /// The order corners are taken in: strongest first, ties by row, then column (a strict total
  /// order, so any sort gives one sequence whatever order the candidates came in).
  static bool strongerFirst(const CornerCandidate& p, const CornerCandidate& q) {
    if (p.response != q.response) return p.response > q.response;
    return p.v != q.v ? p.v < q.v : p.u < q.u;
  }

 private:
  cv::Mat neighbourhood_max_;       ///< 3x3 maximum of the response
  std::vector<std::uint8_t> keep_;  ///< one row: whether each pixel is a candidate
};

/// The Shi-Tomasi response of an image: per pixel the smaller eigenvalue of the structure tensor
/// summed over a block_size x block_size window, computed in one pass from the Scharr
/// derivatives with row buffers kept between calls (fresh multi-megabyte buffers every frame
/// cost page faults). Pixels within half a block of the border get 0.
class CornerResponse {
 public:
  /// `derivatives`: CV_16SC2 Scharr derivatives (dI/dx, dI/dy: 32 x the gradient in grey levels
  /// per pixel, as cv::buildOpticalFlowPyramid stores them). `response` becomes CV_32FC1 of
  /// their size (reallocated only when its size or type differs: it must not share its buffer
  /// with anything that still reads it). Returns the strongest response. Throws
  /// std::invalid_argument on a wrong type or a block size < 1.
  float compute(const cv::Mat& derivatives, int block_size, cv::Mat& response);

  /// Whether the strongest response reaches `floor`: compute(derivatives, ...) >= floor, with
  /// the same values computed row by row in the same way, but stopping at the first rows that
  /// have one (a textured image is decided in its first rows, a bare one costs a whole pass).
  bool reaches(const cv::Mat& derivatives, int block_size, float floor);

 private:
  /// `derivative(v, ix, iy)` fills row v's derivatives. The response rows go to `response`
  /// (nullptr: to a scratch row). Stops once the strongest response so far reaches `stop_at`
  /// (checked every few rows), returning it.
  template <typename RowDerivatives>
  float computeRows(int w, int h, int block_size, RowDerivatives derivative, cv::Mat* response,
                    float stop_at);
  std::vector<float> ix_, iy_;      ///< derivatives of one row
  std::vector<float> column_max_;   ///< strongest response per column so far
  std::vector<float> ring_;         ///< row sums of the products for the last block_size rows
  std::vector<float> products_;     ///< Ix^2, Ix Iy, Iy^2 of one row
  std::vector<float> sums_;         ///< window sums of one row (three planes) and a square-root row
  std::vector<float> scratch_row_;  ///< a response row nobody keeps (reaches())
};

/// Shi-Tomasi corners: the response is the smaller eigenvalue of the structure tensor summed over
/// a block_size x block_size window; a corner is a 3x3 local maximum of the response, at least
/// `quality` times the strongest response inside the mask. Corners are taken strongest first
/// (ties by row, then column) while they keep `spacing`'s minimum distance to everything
/// accepted so far. This is the rule of cv::goodFeaturesToTrack, computed from the Scharr
/// derivatives of the KLT pyramid instead of a second derivative pass (CornerResponse).
class CornerDetector {
 public:
  /// Scharr derivatives of a unit grey-level ramp: (3 + 10 + 3) x 2.
  static constexpr double kScharrScale = 32.0;

  /// Computes the response image of the next detect() calls (CornerResponse on `derivatives`;
  /// same errors).
  void computeResponse(const cv::Mat& derivatives, int block_size);

  /// The response a corner needs to have, per pixel of its block, min_gradient^2
  /// [(grey levels/px)^2] of gradient along its weaker direction.
  static double responseFloor(int block_size, double min_gradient);

  /// Whether any response of the image of `derivatives` (as computeResponse) reaches the floor
  /// of min_gradient: does the view have texture at all? Decided without the whole response
  /// image where possible (CornerResponse::reaches).
  bool hasCorner(const cv::Mat& derivatives, int block_size, double min_gradient);

  /// Corners of the last computeResponse(): `mask` CV_8UC1 of the image's size, nonzero where
  /// corners may be. A corner's response must reach `quality` x the strongest allowed one and
  /// responseFloor(min_gradient). Accepted corners are added to `spacing` and returned.
  std::vector<cv::Point2f> detect(const cv::Mat& mask, int max_corners, double quality,
                                  double min_gradient, FeatureSpacing& spacing);

  /// More corners from the candidates of the last detect() call, continuing after the last one
  /// taken (the same order and spacing rule): for a caller that refused some of the corners it
  /// got. Empty when the candidates are used up.
  std::vector<cv::Point2f> detectMore(int max_corners, FeatureSpacing& spacing);

  /// The response image of the last computeResponse() (CV_32FC1; 0 within half a block of the
  /// border), for tests and diagnostics.
  const cv::Mat& response() const { return response_; }

 private:
  CornerResponse computer_;
  cv::Mat response_;    ///< computeResponse()'s result (reused buffer)
  int block_size_ = 0;  ///< of response_
  /// Of the last detect(): [0, sorted_end_) strongest first, the rest weaker, in any order.
  std::vector<CornerCandidate> candidates_;
  std::vector<float> column_max_;  ///< detect()'s work buffer
  CornerCandidates collector_;
  size_t next_candidate_ = 0;  ///< first candidate detectMore() looks at
  size_t sorted_end_ = 0;
};

}  // namespace rgbdi::frontend
