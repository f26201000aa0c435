// Colours of the navigation-map pictures and scene objects.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "rgbdi/navmap/nav_map.h"

namespace rgbdi::navmap::detail {

using Rgb = std::array<std::uint8_t, 3>;

inline Rgb stateColour(CellState s) {
  switch (s) {
    case CellState::kUnknown:
      return {128, 128, 128};
    case CellState::kFree:
      return {255, 255, 255};
    case CellState::kObstacle:
      return {0, 0, 0};
    case CellState::kTooSteep:
      return {255, 140, 0};
    case CellState::kStepEdge:
      return {220, 0, 0};
    case CellState::kRaised:
      return {110, 0, 0};
    case CellState::kLowered:
      return {0, 60, 220};
  }
  return {255, 0, 255};
}

/// Red (0) - yellow (0.5) - green (1); black where not traversable, grey where unknown.
inline Rgb traversabilityColour(const NavMap& m, std::size_t i) {
  if (m.state[i] == CellState::kUnknown) return {128, 128, 128};
  const float t = m.traversability[i];
  if (!(t > 0.0f)) return {0, 0, 0};
  const float r = t < 0.5f ? 1.0f : 2.0f * (1.0f - t);
  const float g = t < 0.5f ? 2.0f * t : 1.0f;
  return {static_cast<std::uint8_t>(std::lround(255 * r)),
          static_cast<std::uint8_t>(std::lround(230 * g)), 0};
}

}  // namespace rgbdi::navmap::detail
