// The front end's per-image work that depends on the image alone (the grey conversion, and CLAHE
// when on), done ahead of tracking: the SLAM system prepares each image on the thread that feeds
// it, so that the odometry thread (the critical path of a 30 Hz stream) does less. The KLT
// pyramid is not prepared ahead: built on another core, the two KLT passes that read it right
// after ran a quarter slower (cache misses, measured with perf), more than its own cost. Nor is
// the corner response any more: the tracker computes it from the pyramid's derivatives on the
// images that detect new corners only (most images detect none, FrontendOptions::
// detect_min_missing), and decides whether an image has texture at all from its first rows. The
// result is the same wherever the work is done.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbdi/common/types.h"
#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

/// The options a prepared image depends on: a tracker only uses an image prepared like its own.
struct PreparationRecipe {
  double clahe_clip_limit = 0.0;

  static PreparationRecipe of(const FrontendOptions& options);
  bool operator==(const PreparationRecipe& o) const {
    return clahe_clip_limit == o.clahe_clip_limit;
  }
};

/// One colour image prepared for tracking.
struct PreparedImage {
  double t = 0.0;                 ///< [s] stamp of the frame it was made from
  std::uint64_t frame_index = 0;  ///< RgbdFrame::index of that frame
  PreparationRecipe recipe;
  cv::Mat grey;          ///< CV_8UC1 grey image (equalised when CLAHE is on) that KLT tracks
  double grey_ms = 0.0;  ///< thread CPU [ms] of the grey conversion (and CLAHE)

  /// Pixel buffers behind `grey` (colour conversion, CLAHE), kept for reuse.
  cv::Mat converted_storage, equalised_storage;

  double cpuMs() const { return grey_ms; }
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
};

}  // namespace rgbdi::frontend
