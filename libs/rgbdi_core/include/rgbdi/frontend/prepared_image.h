// The front end's per-image work that depends on the image alone (grey conversion and the
// Shi-Tomasi corner response), done ahead of tracking: the SLAM system prepares each image on
// the thread that feeds it, so that the odometry thread (the critical path of a 30 Hz stream)
// does less. The KLT pyramid is not prepared ahead: built on another core, the two KLT passes
// that read it right after ran a quarter slower (cache misses, measured with perf), more than
// its own cost. The result is the same wherever the work is done.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

class CornerResponse;
class CornerCandidates;

/// The options a prepared image depends on: a tracker only uses an image prepared like its own.
struct PreparationRecipe {
  int block_size = 0;                     ///< [px] of the corner response
  double min_gradient_grey_per_px = 0.0;  ///< texture floor of the corner candidates
  double clahe_clip_limit = 0.0;

  static PreparationRecipe of(const FrontendOptions& options);
  bool operator==(const PreparationRecipe& o) const {
    return block_size == o.block_size && min_gradient_grey_per_px == o.min_gradient_grey_per_px &&
           clahe_clip_limit == o.clahe_clip_limit;
  }
};

/// A 3x3 local maximum of the corner response (at least its 8 neighbours), at pixel (u, v).
struct CornerCandidate {
  float response;
  int u, v;
};

/// One colour image prepared for tracking.
struct PreparedImage {
  double t = 0.0;                 ///< [s] stamp of the frame it was made from
  std::uint64_t frame_index = 0;  ///< RgbdFrame::index of that frame
  PreparationRecipe recipe;
  cv::Mat grey;  ///< CV_8UC1 grey image (equalised when CLAHE is on) that KLT tracks
  /// CV_32FC1 Shi-Tomasi response of `grey` from its Scharr derivatives (the same values as from
  /// the derivatives cv::buildOpticalFlowPyramid stores)
  cv::Mat corner_response;
  float strongest_response = 0.0f;  ///< its largest value
  /// Every 3x3 local maximum of the response of at least `candidate_min_response`, in scan order
  /// (row, then column): the corners a detection may take, whatever its mask (it sorts those its
  /// mask and threshold let through).
  std::vector<CornerCandidate> corner_candidates;
  /// max(the texture floor, the smallest positive float)
  float candidate_min_response = 0.0f;
  double grey_ms = 0.0;      ///< thread CPU [ms] of the grey conversion (and CLAHE)
  double response_ms = 0.0;  ///< thread CPU [ms] of the corner response

  /// Pixel buffers behind `grey` (colour conversion, CLAHE), kept for reuse.
  cv::Mat converted_storage, equalised_storage;

  double cpuMs() const { return grey_ms + response_ms; }
  /// Whether it was made from `frame` with `recipe`.
  bool matches(const RgbdFrame& frame, const PreparationRecipe& r) const;
};

/// Prepares images for FeatureTracker with the tracker's options. Not thread-safe (work buffers
/// are kept between images): one preparer per feeding thread.
class ImagePreparer {
 public:
  /// Throws ConfigError for invalid options.
  explicit ImagePreparer(const FrontendOptions& options);
  ~ImagePreparer();
  ImagePreparer(ImagePreparer&&) noexcept;
  ImagePreparer& operator=(ImagePreparer&&) noexcept;

  /// Whether prepare() takes the frame: it has a CV_8UC3 (RGB) or CV_8UC1 colour image. Other
  /// frames are left to the tracker, which refuses them with a message naming the frame.
  static bool accepts(const RgbdFrame& frame);

  /// The frame prepared into `out`, reusing its buffers (a PreparedImage that nothing else refers
  /// to any more, e.g. one whose tracking is done, or a new one). Throws std::invalid_argument
  /// for a frame accepts() refuses.
  void prepare(const RgbdFrame& frame, PreparedImage& out);
  PreparedImage prepare(const RgbdFrame& frame);

  /// Only the grey image, into the preparer's own buffers (valid until the next call; a CV_8UC1
  /// image without CLAHE is returned as it is), for a tracker that prepares its images itself.
  cv::Mat grey(const RgbdFrame& frame);

  const PreparationRecipe& recipe() const { return recipe_; }

 private:
  /// Grey image of `frame` into `grey`: `converted` (colour images) or `equalised` (CLAHE) hold
  /// its pixels unless the frame's own CV_8UC1 image is used as it is.
  void toGrey(const RgbdFrame& frame, cv::Mat& converted, cv::Mat& equalised, cv::Mat& grey) const;

  PreparationRecipe recipe_;
  cv::Ptr<cv::CLAHE> clahe_;  ///< only when clahe_clip_limit > 0
  cv::Mat grey_, equalised_;  ///< grey()'s buffers
  cv::Mat dx_, dy_;           ///< Scharr derivatives (work buffers)
  std::unique_ptr<CornerResponse> response_;
  std::unique_ptr<CornerCandidates> candidates_;
};

}  // namespace rgbdi::frontend
