// Private to the sim world: the parameter interval [t_in, t_out] of a ray inside a convex solid
// and the faces bounding it, shared by the box, cylinder and prism intersections.
#pragma once

#include <limits>

#include "rgbdi/sim/primitives.h"

namespace rgbdi::sim {

struct RayInterval {
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  int face_in = -1, face_out = -1;

  /// The ray enters the solid's half-space/slab through `face` at t.
  void clipEntry(double t, int face) {
    if (t > t_in) {
      t_in = t;
      face_in = face;
    }
  }
  /// The ray leaves it through `face` at t.
  void clipExit(double t, int face) {
    if (t < t_out) {
      t_out = t;
      face_out = face;
    }
  }
  bool empty() const { return t_in > t_out; }
  /// The visible surface: the entry when it lies ahead of the origin, else (origin inside the
  /// solid) the exit face; nothing beyond t_max.
  bool visibleHit(double t_max, PrimitiveHit& hit) const {
    if (empty()) return false;
    if (t_in > kMinHitDistance) {
      if (t_in > t_max) return false;
      hit = {t_in, face_in};
      return true;
    }
    if (t_out > kMinHitDistance && t_out <= t_max) {
      hit = {t_out, face_out};
      return true;
    }
    return false;
  }
};

}  // namespace rgbdi::sim
