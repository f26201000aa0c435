// A function built from smooth steps, with its exact antiderivative.
//
//   f(x) = base + sum_i delta_i * S((x - start_i) / width_i)
//   F(x) = integral of f from 0 to x
//
// S is the degree-7 "smoothstep" 35u^4 - 84u^5 + 70u^6 - 20u^7 on [0, 1] (0 before, 1 after): its
// first three derivatives vanish at both ends, so f is C3 and F is C4. The simulator builds speed
// profiles (speed steps -> arc length), curvature profiles (curvature steps -> heading) and slope
// profiles (slope steps -> height) from it; everything is a polynomial piece, so Taylor
// arithmetic differentiates it exactly.
#pragma once

#include <array>
#include <vector>

#include "rgbdi/sim/motion_taylor.h"

namespace rgbdi::sim {

class SmoothSteps {
 public:
  explicit SmoothSteps(double base = 0.0) : base_(base) {}

  /// Adds a transition by `delta` that starts at `start` and is complete at `start + width`.
  /// Throws std::invalid_argument when width is not positive.
  void addStep(double start, double width, double delta);

  double base() const { return base_; }
  /// Start and end of every transition (where the polynomial pieces change).
  std::vector<double> breakpoints() const;

  template <int K>
  Taylor<K> value(const Taylor<K>& x) const {
    Taylor<K> r(base_);
    for (const Step& s : steps_) r += s.delta * piece(kStep, (x - s.start) / s.width, 0.0);
    return r;
  }
  /// Integral of f from 0 to x.
  template <int K>
  Taylor<K> integral(const Taylor<K>& x) const {
    Taylor<K> r = base_ * x;
    for (const Step& s : steps_) {
      const Taylor<K> u = (x - s.start) / s.width;
      // Past the end the integral of S grows linearly: u - 1/2.
      Taylor<K> piece_value = u.value() >= 1.0 ? u - 0.5 : piece(kStepIntegral, u, 0.0);
      r += s.delta * s.width * (piece_value - s.integral_at_zero);
    }
    return r;
  }
  double value(double x) const { return value(Taylor<0>(x)).value(); }
  double integral(double x) const { return integral(Taylor<0>(x)).value(); }

 private:
  struct Step {
    double start, width, delta;
    double integral_at_zero;  ///< integral of S from its start to x = 0 (so that F(0) = 0)
  };
  static constexpr std::array<double, 8> kStep{0, 0, 0, 0, 35, -84, 70, -20};
  static constexpr std::array<double, 9> kStepIntegral{0, 0, 0, 0, 0, 7, -14, 10, -2.5};

  /// Polynomial p on [0, 1]; `below` before 0 and p(1) after 1 (for S both ends are flat).
  template <int K, size_t N>
  static Taylor<K> piece(const std::array<double, N>& p, const Taylor<K>& u, double below) {
    if (u.value() <= 0.0) return Taylor<K>(below);
    if (u.value() >= 1.0) {
      double at_one = 0.0;
      for (double c : p) at_one += c;
      return Taylor<K>(at_one);
    }
    return polynomial(p, u);
  }

  double base_;
  std::vector<Step> steps_;
};

}  // namespace rgbdi::sim
