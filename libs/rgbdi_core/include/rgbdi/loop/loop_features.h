// ORB keypoints of a keyframe's colour image for loop closure: FAST corners spread over the image
// by grid bucketing, 256-bit ORB descriptors, and depth-backed 3-D points in the colour camera
// frame. Independent of the KLT features of the front end (those are chosen for tracking, these
// for recognising a place seen again from a similar viewpoint).
#pragma once

#include <functional>
#include <memory>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/types.h"
#include "rgbdi/frontend/frontend_options.h"
#include "rgbdi/loop/depth_grid.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::loop {

/// Descriptor type string and size of the sets produced here.
inline constexpr const char* kLoopDescriptorType = "ORB-256";
inline constexpr std::uint32_t kLoopDescriptorBytes = 32;

/// [loop] keys with prefix feature_. Defaults equal share/config.ini.
struct LoopFeatureOptions {
  int max_keypoints = 400;  ///< [count] keypoints kept per keyframe
  /// [count] FAST corners proposed by the detector (over all pyramid levels) before bucketing;
  /// more than max_keypoints so that weakly textured cells still get their share.
  int detect_candidates = 2000;
  int fast_threshold = 20;     ///< [grey level] FAST intensity difference threshold
  int pyramid_levels = 4;      ///< [count] ORB scale levels (1 = full resolution only)
  double pyramid_scale = 1.2;  ///< [unitless] scale factor between two levels
  int border_px = 31;          ///< [px] no keypoint closer than this to the image edge
  int grid_cols = 8;           ///< [count] bucketing grid: columns
  int grid_rows = 6;           ///< [count] bucketing grid: rows
  // --- depth of a keypoint (3-D point for PnP and 3-D/3-D verification) ---
  double depth_min_m = 0.3;                 ///< [m] nearest accepted keypoint depth
  double depth_max_m = 6.0;                 ///< [m] farthest accepted keypoint depth
  int depth_window_px = 2;                  ///< [px] half-size of the hole/edge check window
  double depth_max_relative_spread = 0.03;  ///< [unitless] (max-min)/median allowed in it
  double depth_noise_coeff = 0.004;         ///< [1/m] sensor depth sigma = coeff * z^2
  double depth_max_noise_sigmas = 5.0;      ///< [unitless] noise allowance of the spread test
  // --- depth grid (free-space check of verification; 0 x 0 = none) ---
  int depth_grid_cols = 32;  ///< [count] depth samples per row of the keyframe's depth grid
  int depth_grid_rows = 24;  ///< [count] rows of the depth grid

  /// Throws ConfigError when a value is out of range or inconsistent with another one.
  void validate() const;
  /// Reads the feature_ keys of [loop]; missing keys keep the defaults above.
  static LoopFeatureOptions load(IniReader& ini);
  /// The depth-sampling parameters in the form frontend::sampleDepth takes (registration keys
  /// of `base` are kept).
  frontend::FrontendOptions depthSampling(
      const frontend::FrontendOptions& base = frontend::FrontendOptions()) const;
};

/// Extracts loop features frame after frame. Keeps the depth registrar (its cached rays of the
/// depth camera) between calls; one instance per stream. Not thread-safe; deterministic.
class LoopFeatureExtractor {
 public:
  /// `registration` supplies the depth-registration keys ([frontend]) used when depth is not
  /// aligned to colour. Throws ConfigError on invalid options.
  explicit LoopFeatureExtractor(
      const LoopFeatureOptions& options,
      const frontend::FrontendOptions& registration = frontend::FrontendOptions());
  ~LoopFeatureExtractor();
  LoopFeatureExtractor(const LoopFeatureExtractor&) = delete;
  LoopFeatureExtractor& operator=(const LoopFeatureExtractor&) = delete;

  /// ORB keypoints of frame.rgb (distorted pixels of `cam`), at most max_keypoints, type
  /// "ORB-256". keypoints_p_cam is size() long when the frame has depth (NaN where the depth at
  /// the keypoint is missing, out of range or on a depth edge) and empty when it has none.
  /// A frame without colour gives an empty set. Throws std::invalid_argument naming
  /// frame.source_label when the colour image does not match `cam` or is not CV_8UC3.
  /// `to_stamp` (rolling shutter): maps a keypoint's pixel as seen to its pixel at the frame's
  /// stamp, where keypoints_uv and the depth (a global-shutter image at the stamp) are taken.
  mapping::DescriptorSet extract(
      const RgbdFrame& frame, const PinholeCamera& cam,
      const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& to_stamp = {});

  /// The frame's depth registered to `cam` and sampled (with the keypoints' hole/edge and range
  /// rules) at the centres of a depth_grid_cols x depth_grid_rows grid. Empty when the frame has
  /// no depth or the grid is 0 x 0. Throws std::invalid_argument as extract() does.
  DepthGrid depthGrid(const RgbdFrame& frame, const PinholeCamera& cam);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot extraction (builds a LoopFeatureExtractor for this frame).
mapping::DescriptorSet extractLoopFeatures(const RgbdFrame& frame, const PinholeCamera& cam,
                                           const LoopFeatureOptions& options);

}  // namespace rgbdi::loop
