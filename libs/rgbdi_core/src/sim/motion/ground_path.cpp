#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rgbdi/sim/motion_ground_path.h"

namespace rgbdi::sim {
namespace {

// Knot spacing of the quadrature [m]: with 10 Gauss-Legendre points per interval and curvature
// below a few 1/m the integration error is at round-off level.
constexpr double kKnotSpacing = 0.25;
constexpr int kGaussPoints = 10;

struct GaussLegendre {
  std::array<double, kGaussPoints> x{}, w{};
};

// Nodes and weights on [-1, 1] from Newton iterations on the Legendre polynomial.
GaussLegendre makeGaussLegendre() {
  GaussLegendre g;
  const int n = kGaussPoints;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(M_PI * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    g.x[static_cast<size_t>(i)] = x;
    g.w[static_cast<size_t>(i)] = 2.0 / ((1.0 - x * x) * dp * dp);
  }
  return g;
}

const GaussLegendre& gaussLegendre() {
  static const GaussLegendre g = makeGaussLegendre();  // immutable after initialisation
  return g;
}

}  // namespace

GroundPath::GroundPath(SmoothSteps curvature, SmoothSteps slope, const Eigen::Vector2d& start_xy,
                       double start_z, double start_heading, double length)
    : curvature_(std::move(curvature)),
      slope_(std::move(slope)),
      xy0_(start_xy),
      z0_(start_z),
      heading0_(start_heading),
      length_(length) {
  if (!(length > 0.0) || !std::isfinite(length))
    throw std::invalid_argument("GroundPath: length must be positive (got " +
                                std::to_string(length) + ")");
  const int n = static_cast<int>(std::ceil(length / kKnotSpacing));
  for (int i = 0; i <= n; ++i) knots_.push_back(std::min(length, i * kKnotSpacing));
  for (double b : curvature_.breakpoints())
    if (b > 0.0 && b < length) knots_.push_back(b);
  std::sort(knots_.begin(), knots_.end());
  knots_.erase(std::unique(knots_.begin(), knots_.end(),
                           [](double a, double b) { return std::abs(a - b) < 1e-12; }),
               knots_.end());
  knot_xy_.reserve(knots_.size());
  knot_xy_.push_back(xy0_);
  for (size_t i = 1; i < knots_.size(); ++i)
    knot_xy_.push_back(knot_xy_.back() + tangentIntegral(knots_[i - 1], knots_[i]));
}

Eigen::Vector2d GroundPath::tangentIntegral(double s0, double s1) const {
  const GaussLegendre& g = gaussLegendre();
  const double half = 0.5 * (s1 - s0), mid = 0.5 * (s1 + s0);
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (int i = 0; i < kGaussPoints; ++i) {
    const double th = heading(mid + half * g.x[static_cast<size_t>(i)]);
    sum += g.w[static_cast<size_t>(i)] * Eigen::Vector2d(std::cos(th), std::sin(th));
  }
  return half * sum;
}

Eigen::Vector2d GroundPath::xy(double s) const {
  if (s <= 0.0) {
    // Before the start the path continues straight back along the initial tangent.
    return xy0_ + s * Eigen::Vector2d(std::cos(heading0_), std::sin(heading0_));
  }
  // Last knot <= s; the interval [knot, s] contains no breakpoint.
  const auto it = std::upper_bound(knots_.begin(), knots_.end(), s);
  const size_t i = static_cast<size_t>(std::distance(knots_.begin(), it)) - 1;
  if (s > knots_.back()) {
    // Past the end: integrate in knot-sized pieces so accuracy holds (breakpoints there are rare).
    Eigen::Vector2d p = knot_xy_.back();
    double a = knots_.back();
    while (a < s) {
      const double b = std::min(s, a + kKnotSpacing);
      p += tangentIntegral(a, b);
      a = b;
    }
    return p;
  }
  return knot_xy_[i] + tangentIntegral(knots_[i], s);
}

GroundPoint GroundPath::at(const Taylor<3>& s) const {
  GroundPoint g;
  g.heading = heading0_ + curvature_.integral(s);
  g.slope = slope_.value(s);
  // d(xy)/dt = (cos theta, sin theta) * ds/dt; the value itself comes from the quadrature.
  Taylor<2> c, sn;
  sincos(g.heading.truncated<2>(), sn, c);
  const Taylor<2> sdot = s.differentiated();
  const Eigen::Vector2d p = xy(s.value());
  g.position[0] = (c * sdot).integrated(p.x());
  g.position[1] = (sn * sdot).integrated(p.y());
  g.position[2] = z0_ + slope_.integral(s);
  return g;
}

}  // namespace rgbdi::sim
