// Coloured 3-D points of the map: as kept by a keyframe (camera frame) and as held by the map
// (world frame).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>

namespace rgbdi::mapping {

using Rgb = std::array<std::uint8_t, 3>;  ///< R, G, B

/// Grey given to points of frames without a colour image.
inline constexpr Rgb kUncolouredRgb{128, 128, 128};

/// A point kept by a keyframe, in that keyframe's colour-camera optical frame [m]. Storing the
/// points in the camera frame lets the map be rebuilt from corrected keyframe poses.
struct MapPoint {
  Eigen::Vector3f p_cam = Eigen::Vector3f::Zero();
  Rgb rgb{0, 0, 0};
};

/// A point of the map in the world frame [m].
struct WorldPoint {
  Eigen::Vector3f p_world = Eigen::Vector3f::Zero();
  Rgb rgb{0, 0, 0};
};

}  // namespace rgbdi::mapping
