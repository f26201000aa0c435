// Depth registered to the colour image: metres per colour pixel, whatever the source geometry.
#pragma once

#include <opencv2/core.hpp>

#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/types.h"
#include "rgbdi/frontend/frontend_options.h"

namespace rgbdi::frontend {

/// Registers depth images to a colour camera. Keeps the undistorted viewing rays of the depth
/// camera between calls (rebuilt when its intrinsics change), so one instance per stream avoids
/// re-inverting the distortion model for every pixel of every frame.
///
/// Method when depth is not aligned to colour: every valid depth pixel is back-projected with
/// the depth intrinsics (incl. distortion), moved by T_color_depth and projected with the colour
/// intrinsics (incl. distortion). Two z-buffers (smallest z wins) are filled from it:
///  - values: each point is written to its nearest colour pixel only (accurate values);
///  - cover: each point is splatted 2x2 (the four pixels around its sub-pixel position), which
///    closes the 1-pixel cracks of a magnified depth image and tells which surface is in front.
/// A pixel keeps its value when it is not behind its cover (by more than
/// registration_fill_max_relative_diff). Otherwise (a crack, or background seen through a crack
/// of a nearer surface) it takes the mean of two opposite trusted neighbours (horizontal,
/// vertical or diagonal) that agree within that fraction and are not behind the cover, else the
/// cover value. So cracks are interpolated, occluded background never shows through, foreground
/// grows by at most one pixel at depth edges, and no pixel farther than one pixel from any depth
/// point gets a value (disoccluded areas stay empty).
class DepthRegistrar {
 public:
  explicit DepthRegistrar(const FrontendOptions& options = FrontendOptions());

  /// CV_32FC1 depth [m] along the colour camera's optical axis in the geometry of `cam_color`
  /// (0 = no data). `frame.cam_color` is ignored in favour of `cam_color`. Throws
  /// std::invalid_argument naming frame.source_label when the depth image or calibration is
  /// unusable (wrong type, size not matching the camera, invalid intrinsics).
  cv::Mat registerDepth(const RgbdFrame& frame, const PinholeCamera& cam_color);

 private:
  void updateRays(const PinholeCamera& cam_depth);

  FrontendOptions options_;
  PinholeCamera rays_camera_;    ///< intrinsics the cached rays belong to
  std::vector<float> rays_xn_;   ///< interleaved undistorted (x/z, y/z) per depth pixel
};

/// One-shot registration with the frame's own colour intrinsics (see DepthRegistrar).
cv::Mat registerDepthToColor(const RgbdFrame& frame, const FrontendOptions& options = FrontendOptions());

}  // namespace rgbdi::frontend
