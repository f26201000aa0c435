// Depth registered to the colour image: metres per colour pixel, whatever the source geometry.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/types.h"
#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

/// Registers depth images to a colour camera. Keeps the undistorted viewing rays of the depth
/// camera and its work buffers between calls (rays rebuilt when the intrinsics change), so one
/// instance per stream avoids re-inverting the distortion model for every pixel of every frame.
///
/// Method when depth is not aligned to colour: every valid depth pixel is back-projected with
/// the depth intrinsics (incl. distortion), moved by T_color_depth, projected with the colour
/// intrinsics (incl. distortion) and written to its nearest colour pixel, keeping the smallest z
/// (z-buffer). A second z-buffer, the "cover", receives each point on the 2x2 pixels around its
/// sub-pixel position: it closes 1-pixel cracks and tells which surface is in front. A pixel keeps
/// its own value when that is not behind its cover by more than
/// registration_fill_max_relative_diff. Otherwise (a crack left by a magnified depth image, or
/// background seen through such a crack in a nearer surface) it takes the mean of two opposite
/// trusted neighbours (horizontal, vertical or diagonal) that agree within that fraction and are
/// not behind the cover, else the cover itself. So cracks are interpolated, occluded background
/// never shows through, foreground grows by less than one pixel at depth edges, and a pixel with no
/// depth point within one pixel stays empty (disoccluded areas stay empty).
class DepthRegistrar {
 public:
  explicit DepthRegistrar(const FrontendOptions& options = FrontendOptions());

  /// CV_32FC1 depth [m] along the colour camera's optical axis in the geometry of `cam_color`
  /// (0 = no data). `frame.cam_color` is ignored in favour of `cam_color`. Throws
  /// std::invalid_argument naming frame.source_label when the depth image or calibration is
  /// unusable (wrong type, size not matching the camera, invalid intrinsics).
  cv::Mat registerDepth(const RgbdFrame& frame, const PinholeCamera& cam_color);

  /// The same values as registerDepth(), computed only for the colour pixels within `radius_px`
  /// (Chebyshev distance) of the rounded `centres`; every other pixel of `out` is 0. Only the
  /// depth pixels that can land near those pixels are projected (found from the nearest depth in
  /// the frame and the camera geometry), which makes per-feature depth cheap. `out` is
  /// (re)allocated as CV_32FC1 of the colour image size.
  void registerDepthAround(const RgbdFrame& frame, const PinholeCamera& cam_color,
                           const std::vector<Eigen::Vector2d>& centres, int radius_px,
                           cv::Mat& out);
  /// Adds the windows around further `centres` to `out` of the last registerDepthAround() call,
  /// which must have been made with the same `frame` and `cam_color` (the depth points projected
  /// then are kept); pixels already registered keep their values.
  void registerMoreDepthAround(const RgbdFrame& frame, const PinholeCamera& cam_color,
                               const std::vector<Eigen::Vector2d>& centres, int radius_px,
                               cv::Mat& out);

 private:
  /// Validates the frame; for unaligned depth also prepares rays, projection and buffers.
  void prepare(const RgbdFrame& frame, const PinholeCamera& cam_color);
  void updateRays(const PinholeCamera& cam_depth);
  /// Projects the valid depth pixels inside `depth_roi` into values_ and cover_; with `skip_done`
  /// only those splatted_ does not mark yet (and marks them). The z-buffers take minima, so a
  /// pixel projected twice changes nothing: overlapping windows are projected once.
  void splat(const RgbdFrame& frame, const cv::Rect& depth_roi, bool skip_done = false);
  /// Depth pixels that can land in colour rectangle `colour_rect` when no depth point is nearer
  /// than `nearest_range_m` to the depth camera.
  cv::Rect depthRoiFor(const cv::Rect& colour_rect, double nearest_range_m, const RgbdFrame& frame,
                       const PinholeCamera& cam_color) const;
  /// Writes the final depth of the pixels in `rect` to `out` (needs values_ and cover_ one pixel
  /// around `rect`).
  void resolve(const cv::Rect& rect, cv::Mat& out) const;
  /// Registers the windows around `centres` into `out` (prepared by the caller).
  void registerWindows(const RgbdFrame& frame, const PinholeCamera& cam_color,
                       const std::vector<Eigen::Vector2d>& centres, int radius_px, cv::Mat& out);

  FrontendOptions options_;
  PinholeCamera rays_camera_;   ///< intrinsics the cached rays belong to
  std::vector<float> rays_xn_;  ///< interleaved undistorted (x/z, y/z) per depth pixel
  PinholeCamera cam_color_;     ///< colour camera of the current call
  Eigen::Matrix3f R_color_depth_;
  Eigen::Vector3f t_color_depth_;
  float max_radius2_ = 0.0f;  ///< projection validity bound (see maxNormalisedRadius2)
  cv::Mat values_;            ///< nearest-pixel z-buffer, +max float = no point
  cv::Mat cover_;             ///< 2x2-footprint z-buffer, +max float = no point
  cv::Mat splatted_;          ///< CV_8U, depth image size: 1 = projected in this frame
  double nearest_range_m_ =
      0.0;                  ///< of the current frame: no depth point is nearer (0 = none known)
  bool any_depth_ = false;  ///< the current frame has a valid depth pixel
};

/// One-shot registration with the frame's own colour intrinsics (see DepthRegistrar).
cv::Mat registerDepthToColor(const RgbdFrame& frame,
                             const FrontendOptions& options = FrontendOptions());

}  // namespace rgbdi::frontend
