// Shi-Tomasi corner detection from image derivatives that the KLT pyramid already holds.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

namespace rgbdi::frontend {

class FeatureSpacing;

/// Shi-Tomasi corners: the response is the smaller eigenvalue of the structure tensor summed over
/// a block_size x block_size window; a corner is a 3x3 local maximum of the response, at least
/// `quality` times the strongest response inside the mask. Corners are taken strongest first
/// (ties by row, then column) while they keep `spacing`'s minimum distance to everything
/// accepted so far. This is the rule of cv::goodFeaturesToTrack, computed from the Scharr
/// derivatives of the KLT pyramid instead of a second derivative pass, in a single pass with
/// row buffers kept between calls (fresh multi-megabyte buffers every frame cost page faults).
/// Pixels within half a block of the border get no response.
class CornerDetector {
 public:
  /// Scharr derivatives of a unit grey-level ramp: (3 + 10 + 3) x 2.
  static constexpr double kScharrScale = 32.0;

  /// Computes the response image of the next detect() / isCorner() calls. `derivatives`:
  /// CV_16SC2 Scharr derivatives (dI/dx, dI/dy: 32 x the gradient in grey levels per pixel, as
  /// cv::buildOpticalFlowPyramid stores them). Throws std::invalid_argument on a wrong type or a
  /// block size < 1.
  void computeResponse(const cv::Mat& derivatives, int block_size);

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

  /// The response image of the last computeResponse() (CV_32FC1; 0 within half a block of the
  /// border), for tests and diagnostics.
  const cv::Mat& response() const { return response_; }

 private:
  cv::Mat response_;
  int block_size_ = 0;           ///< of response_
  std::vector<float> ring_;      ///< row sums of the products for the last block_size rows
  std::vector<float> products_;  ///< Ix^2, Ix Iy, Iy^2 of one row
  std::vector<float> sums_;      ///< window sums of one row (three planes) and a square-root row
  struct Candidate {
    float response;
    int u, v;
  };
  std::vector<Candidate> candidates_;  ///< of the last detect(), strongest first
  size_t next_candidate_ = 0;          ///< first candidate detectMore() looks at
};

}  // namespace rgbdi::frontend
