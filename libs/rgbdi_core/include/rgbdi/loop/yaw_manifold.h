// Yaw angle parameter of the 4-DOF pose graph as a ceres::Manifold: Plus and Minus wrap the
// result to [-pi, pi), so a heading stays a valid angle however far the solver moves it and the
// difference of two headings is the short way round (179 deg - (-179 deg) = -2 deg).
#pragma once

#include <ceres/manifold.h>

namespace rgbdi::loop {

/// a wrapped to [-pi, pi).
double wrapAngle(double a);

class YawManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 1; }
  int TangentSize() const override { return 1; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override;
  bool PlusJacobian(const double* x, double* jacobian) const override;
  bool Minus(const double* y, const double* x, double* y_minus_x) const override;
  bool MinusJacobian(const double* x, double* jacobian) const override;
};

}  // namespace rgbdi::loop
