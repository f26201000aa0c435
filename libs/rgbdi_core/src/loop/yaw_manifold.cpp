#include "rgbdi/loop/yaw_manifold.h"

#include <cmath>

namespace rgbdi::loop {

double wrapAngle(double a) {
  constexpr double kTwoPi = 2.0 * M_PI;
  double r = a - kTwoPi * std::floor((a + M_PI) / kTwoPi);
  // floor() is exact, but the subtraction can round onto the excluded end of the interval.
  if (r >= M_PI) r -= kTwoPi;
  if (r < -M_PI) r += kTwoPi;
  return r;
}

bool YawManifold::Plus(const double* x, const double* delta, double* x_plus_delta) const {
  x_plus_delta[0] = wrapAngle(x[0] + delta[0]);
  return true;
}

bool YawManifold::PlusJacobian(const double* /*x*/, double* jacobian) const {
  jacobian[0] = 1.0;
  return true;
}

bool YawManifold::Minus(const double* y, const double* x, double* y_minus_x) const {
  y_minus_x[0] = wrapAngle(y[0] - x[0]);
  return true;
}

bool YawManifold::MinusJacobian(const double* /*x*/, double* jacobian) const {
  jacobian[0] = 1.0;
  return true;
}

}  // namespace rgbdi::loop
