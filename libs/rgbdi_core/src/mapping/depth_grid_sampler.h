// Subsampling of a depth image on a regular pixel grid (paper section 4.5): back-projects the
// grid pixels with valid depth into the colour camera optical frame and attaches their colour.
// Shared by the point map and the occupancy map. Normalised rays of the grid are cached per
// camera, so the per-frame cost is one multiply per point (no undistortion iterations).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/map_point.h"

namespace rgbdi::mapping::detail {

struct GridRect {
  int step_px = 10;
  int u_min_px = 0, u_max_px = 0, v_min_px = 0, v_max_px = 0;
};

struct GridSampleCounts {
  std::uint64_t grid_points = 0;   ///< grid pixels visited
  std::uint64_t no_depth = 0;      ///< depth 0 (invalid)
  std::uint64_t out_of_range = 0;  ///< depth outside (z_min, z_max)
  std::uint64_t kept = 0;          ///< returned points
};

class DepthGridSampler {
 public:
  explicit DepthGridSampler(const GridRect& grid) : grid_(grid) {}

  /// Appends to `out` (camera frame = colour camera optical frame) every point of the grid,
  /// taking every `stride`-th grid row and column, whose depth z satisfies z_min < z < z_max,
  /// in row-major order. Throws std::invalid_argument naming the frame's source when the frame
  /// cannot be used (no or wrongly typed depth, image sizes that disagree with the cameras, a
  /// grid outside the image).
  void sample(const RgbdFrame& frame, int stride, double z_min, double z_max,
              std::vector<MapPoint>& out, GridSampleCounts& counts);

 private:
  struct RayCache {
    PinholeCamera camera;
    std::vector<int> us, vs;          // grid columns / rows inside the image
    std::vector<Eigen::Vector2f> xn;  // undistorted normalised ray per (row, column)
  };
  const RayCache& raysFor(const PinholeCamera& camera, const std::string& label);

  GridRect grid_;
  RayCache cache_;
  bool cache_valid_ = false;
};

/// "<source_label>" or "frame <index> (t = <stamp>)" for messages.
std::string frameLabel(const RgbdFrame& frame);

}  // namespace rgbdi::mapping::detail
