// Shi-Tomasi corner detection from image derivatives that the KLT pyramid already holds.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "rgbdi/frontend/prepared_image.h"

namespace rgbdi::frontend {

class FeatureSpacing;

/// Corner candidates of a response image: its 3x3 local maxima. Work buffers are kept between
/// calls.
class CornerCandidates {
 public:
  /// Appends the 3x3 local maxima of `response` (at least each of their 8 neighbours; none on
  /// the outermost pixel rows and columns) with a response of at least `min_response` where
  /// `mask` (CV_8UC1, nullptr: everywhere) is nonzero, in scan order (row, then column).
  void collect(const cv::Mat& response, float min_response, const cv::Mat* mask,
               std::vector<CornerCandidate>& out);
  /// Sorts candidates strongest first, ties by row, then column (a total order: the same
  /// sequence whatever order they came in).
  static void sortStrongestFirst(std::vector<CornerCandidate>& candidates);

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
  /// The same from the derivatives as two CV_16SC1 planes (cv::Scharr's dx and dy).
  float compute(const cv::Mat& dx, const cv::Mat& dy, int block_size, cv::Mat& response);

 private:
  /// `derivative(v, ix, iy)` fills row v's derivatives.
  template <typename RowDerivatives>
  float computeRows(int w, int h, int block_size, RowDerivatives derivative, cv::Mat& response);
  std::vector<float> ix_, iy_;     ///< derivatives of one row
  std::vector<float> column_max_;  ///< strongest response per column so far
  std::vector<float> ring_;        ///< row sums of the products for the last block_size rows
  std::vector<float> products_;    ///< Ix^2, Ix Iy, Iy^2 of one row
  std::vector<float> sums_;        ///< window sums of one row (three planes) and a square-root row
};

/// Shi-Tomasi corners: the response is the smaller eigenvalue of the structure tensor summed over
/// a block_size x block_size window; a corner is a 3x3 local maximum of the response, at least
/// `quality` times the strongest response inside the mask. Corners are taken strongest first
/// (ties by row, then column) while they keep `spacing`'s minimum distance to everything
/// accepted so far. This is the rule of cv::goodFeaturesToTrack, computed from the Scharr
/// derivatives of the KLT pyramid instead of a second derivative pass (CornerResponse).
///
/// The response may come from elsewhere (useResponse: an image prepared ahead on another thread,
/// rgbdi/frontend/prepared_image.h) or be computed here (computeResponse).
class CornerDetector {
 public:
  /// Scharr derivatives of a unit grey-level ramp: (3 + 10 + 3) x 2.
  static constexpr double kScharrScale = 32.0;

  /// Computes the response image of the next detect() / hasCorner() calls (CornerResponse on
  /// `derivatives`; same errors).
  void computeResponse(const cv::Mat& derivatives, int block_size);

  /// Uses a response prepared elsewhere (PreparedImage: the response with its block size, its
  /// strongest value and its local maxima; read in place, not copied: `prepared` must stay
  /// unchanged until releaseResponse(), computeResponse() or the next useResponse()). detect()
  /// then filters the prepared candidates
  /// instead of scanning the image, with the same result. Throws std::invalid_argument unless
  /// the response is CV_32FC1 and block_size >= 1.
  void useResponse(const PreparedImage& prepared, int block_size);

  /// The response a corner needs to have, per pixel of its block, min_gradient^2
  /// [(grey levels/px)^2] of gradient along its weaker direction.
  static double responseFloor(int block_size, double min_gradient);

  /// Whether any response of the image reaches the floor of min_gradient: does the view have
  /// texture at all?
  bool hasCorner(double min_gradient) const;

  /// Corners of the last computeResponse(): `mask` CV_8UC1 of the image's size, nonzero where
  /// corners may be. A corner's response must reach `quality` x the strongest allowed one and
  /// responseFloor(min_gradient). Accepted corners are added to `spacing` and returned.
  std::vector<cv::Point2f> detect(const cv::Mat& mask, int max_corners, double quality,
                                  double min_gradient, FeatureSpacing& spacing);

  /// More corners from the candidates of the last detect() call, continuing after the last one
  /// taken (the same order and spacing rule): for a caller that refused some of the corners it
  /// got. Empty when the candidates are used up.
  std::vector<cv::Point2f> detectMore(int max_corners, FeatureSpacing& spacing);

  /// Lets go of a response given to useResponse() (its buffers may then be reused elsewhere);
  /// detect() and hasCorner() need a computeResponse() or useResponse() again.
  void releaseResponse() {
    response_ = cv::Mat();
    prepared_candidates_ = nullptr;
  }

  /// The response image in use (CV_32FC1; 0 within half a block of the border), for tests and
  /// diagnostics.
  const cv::Mat& response() const { return response_; }

 private:
  CornerResponse computer_;
  cv::Mat own_response_;    ///< computeResponse()'s result (reused buffer)
  cv::Mat response_;        ///< the response in use: own_response_ or one given to useResponse()
  int block_size_ = 0;      ///< of response_
  float strongest_ = 0.0f;  ///< of response_
  /// Prepared local maxima of response_ of at least prepared_min_ (nullptr: none prepared)
  const std::vector<CornerCandidate>* prepared_candidates_ = nullptr;
  float prepared_min_ = 0.0f;
  std::vector<CornerCandidate> candidates_;  ///< of the last detect(), strongest first
  std::vector<float> column_max_;            ///< detect()'s work buffer
  CornerCandidates collector_;
  size_t next_candidate_ = 0;  ///< first candidate detectMore() looks at
};

}  // namespace rgbdi::frontend
