// A smooth path on the ground, parametrised by horizontal arc length s [m].
//
// The heading is theta(s) = theta0 + integral of the curvature profile (smooth steps), so
// curvature changes continuously (no jump in lateral acceleration where a straight meets a
// turn, unlike line + circular-arc paths). The height is z(s) = z0 + integral of the slope
// profile (ramps with rounded edges, as a wheelbase smooths them). The horizontal position has no
// closed form; it is integrated once with Gauss-Legendre quadrature between knots placed at every
// curvature breakpoint (the integrand is analytic between them), which is exact to ~1e-13 m.
// Its derivatives come straight from the tangent (cos theta, sin theta), so velocities and
// accelerations stay exact.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rgbdi/sim/motion_smooth_steps.h"
#include "rgbdi/sim/motion_taylor.h"

namespace rgbdi::sim {

/// The ground path evaluated at one arc length (expansions in time, given s(t)).
struct GroundPoint {
  TaylorVec3<3> position;  ///< world point on the (smoothed) ground under the robot
  Taylor<3> heading;       ///< [rad] direction of travel about world z
  Taylor<3> slope;         ///< dz/ds [unitless] along the direction of travel
};

class GroundPath {
 public:
  /// curvature: kappa(s) [1/m]; slope: dz/ds; the path starts at start_xy, height start_z,
  /// heading start_heading [rad]. Quadrature knots cover [0, length] (longer s is allowed but
  /// integrated from the last knot).
  GroundPath(SmoothSteps curvature, SmoothSteps slope, const Eigen::Vector2d& start_xy,
             double start_z, double start_heading, double length);

  /// The path at arc length s(t) given as a time expansion.
  GroundPoint at(const Taylor<3>& s) const;

  double heading(double s) const { return heading0_ + curvature_.integral(s); }
  double height(double s) const { return z0_ + slope_.integral(s); }
  Eigen::Vector2d xy(double s) const;
  double curvature(double s) const { return curvature_.value(s); }
  double slope(double s) const { return slope_.value(s); }
  double length() const { return length_; }

 private:
  /// Integral of the unit tangent from s0 to s1 (no curvature breakpoint strictly inside).
  Eigen::Vector2d tangentIntegral(double s0, double s1) const;

  SmoothSteps curvature_, slope_;
  Eigen::Vector2d xy0_;
  double z0_, heading0_, length_;
  std::vector<double> knots_;
  std::vector<Eigen::Vector2d> knot_xy_;
};

}  // namespace rgbdi::sim
